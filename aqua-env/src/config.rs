//! The `[sea]` table of a scene (docs/guide/scene.md#sea): serde types with the binding
//! key names, validation with messages that name key, value and valid range, and construction of a
//! [`Sea`] with its printed summary and warnings.

use crate::airy::{Component, LinearSum};
use crate::constants::{
    Constants, Depth, SEA_WATER_DENSITY, SEA_WATER_VISCOSITY, STANDARD_GRAVITY,
};
use crate::current::{Current, CurrentProfile, MAX_CURRENT_SPEED, Schedule};
use crate::dispersion::group_velocity;
use crate::error::EnvError;
use crate::irregular::{IrregularSpec, Spacing, discretise};
use crate::ramp::Ramp;
use crate::sea::{Sea, Waves};
use crate::spectrum::{Spectrum, gamma_auto};
use crate::stokes::Stokes2;
use crate::stretching::Stretching;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

fn default_gravity() -> f64 {
    STANDARD_GRAVITY
}
fn default_density() -> f64 {
    SEA_WATER_DENSITY
}
fn default_viscosity() -> f64 {
    SEA_WATER_VISCOSITY
}
fn default_true() -> bool {
    true
}
fn default_ramp() -> f64 {
    10.0
}
fn default_components() -> usize {
    200
}
fn default_seed() -> u64 {
    1
}
fn default_cutoff() -> f64 {
    1e-3
}

/// `[sea]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeaSpec {
    /// g [m/s²].
    #[serde(default = "default_gravity")]
    pub gravity: f64,
    /// Water depth h [m] (> 0), or "infinite" (waves only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<DepthValue>,
    /// `[sea.water]`.
    #[serde(default)]
    pub water: WaterSpec,
    /// `[sea.current]`.
    #[serde(default)]
    pub current: CurrentSpec,
    /// `[sea.waves]`.
    #[serde(default)]
    pub waves: WavesSpec,
    /// `[sea.seabed]`: contact constants of the flat seabed at z = −depth (used by the
    /// structural solver; carried here because the seabed belongs to the sea).
    #[serde(default)]
    pub seabed: SeabedSpec,
}

impl Default for SeaSpec {
    fn default() -> Self {
        Self {
            gravity: STANDARD_GRAVITY,
            depth: None,
            water: WaterSpec::default(),
            current: CurrentSpec::default(),
            waves: WavesSpec::default(),
            seabed: SeabedSpec::default(),
        }
    }
}

/// `[sea.seabed]` (docs/theory/fem.md#seabed-contact): penalty pressure per metre of penetration
/// and per m/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeabedSpec {
    /// k_b [Pa/m] (default 3e6).
    #[serde(default = "default_kbot")]
    pub kbot: f64,
    /// c_b [Pa·s/m] (default 3e5).
    #[serde(default = "default_cbot")]
    pub cbot: f64,
    /// Penetration δ_c over which c_b ramps in from zero [m] (default 0.01), so that the contact
    /// force is continuous at touchdown.
    #[serde(default = "default_damping_depth")]
    pub damping_depth: f64,
    /// Axial seabed friction coefficient μ_a, along the line (default 0: no friction;
    /// docs/theory/fem.md#seabed-friction).
    #[serde(default)]
    pub friction_axial: f64,
    /// Transverse seabed friction coefficient μ_t (default: `friction_axial`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_transverse: Option<f64>,
    /// Slip velocity v_c of the regularised friction [m/s] (default 1e-2).
    #[serde(default = "default_slip_velocity")]
    pub slip_velocity: f64,
}

impl SeabedSpec {
    /// μ_t: `friction_transverse`, or `friction_axial` when it is not given.
    pub fn transverse_friction(&self) -> f64 {
        self.friction_transverse.unwrap_or(self.friction_axial)
    }

    /// Checks the friction keys: μ ≥ 0 and v_c > 0, finite.
    fn validate_friction(&self) -> Result<(), EnvError> {
        let mut mus = vec![("sea.seabed.friction_axial", self.friction_axial)];
        if let Some(mu) = self.friction_transverse {
            mus.push(("sea.seabed.friction_transverse", mu));
        }
        for (key, mu) in mus {
            if !(mu >= 0.0 && mu.is_finite()) {
                return Err(EnvError::range(
                    key,
                    mu,
                    "a friction coefficient, finite and >= 0 (0 = no friction; chain on sand \
                     about 0.7 axial, 1.0 transverse)",
                ));
            }
        }
        let vc = self.slip_velocity;
        if !(vc > 0.0 && vc.is_finite()) {
            return Err(EnvError::range(
                "sea.seabed.slip_velocity",
                vc,
                "a velocity in m/s, finite and > 0 (default 0.01)",
            ));
        }
        Ok(())
    }
}

fn default_kbot() -> f64 {
    3e6
}
fn default_cbot() -> f64 {
    3e5
}
fn default_damping_depth() -> f64 {
    1e-2
}
fn default_slip_velocity() -> f64 {
    1e-2
}

impl Default for SeabedSpec {
    fn default() -> Self {
        Self {
            kbot: default_kbot(),
            cbot: default_cbot(),
            damping_depth: default_damping_depth(),
            friction_axial: 0.0,
            friction_transverse: None,
            slip_velocity: default_slip_velocity(),
        }
    }
}

/// A depth in metres or the word "infinite".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum DepthValue {
    /// h [m].
    Metres(f64),
    /// Must be "infinite".
    Word(String),
}

/// `[sea.water]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterSpec {
    /// ρ_w [kg/m³].
    #[serde(default = "default_density")]
    pub density: f64,
    /// ν [m²/s].
    #[serde(default = "default_viscosity")]
    pub kinematic_viscosity: f64,
}

impl Default for WaterSpec {
    fn default() -> Self {
        Self {
            density: SEA_WATER_DENSITY,
            kinematic_viscosity: SEA_WATER_VISCOSITY,
        }
    }
}

/// `sea.current.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurrentKind {
    /// No current.
    #[default]
    None,
    /// `velocity`.
    Uniform,
    /// `points`.
    Profile,
    /// `surface_velocity`, `exponent`.
    PowerLaw,
}

/// `[sea.current]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurrentSpec {
    /// Which current.
    #[serde(default)]
    pub kind: CurrentKind,
    /// Uniform velocity [m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<[f64; 3]>,
    /// Profile points [z, ux, uy, uz].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<Vec<[f64; 4]>>,
    /// Power-law surface velocity [m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface_velocity: Option<[f64; 3]>,
    /// Power-law exponent p (default 1/7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exponent: Option<f64>,
    /// Uniform velocity sweep [t_start, ux, uy, uz].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub schedule: Option<Vec<[f64; 4]>>,
    /// Include the current in the static solve.
    #[serde(default = "default_true")]
    pub in_static: bool,
    /// Start-up ramp [s] (used only when dynamics starts without current).
    #[serde(default = "default_ramp")]
    pub ramp_time: f64,
}

impl Default for CurrentSpec {
    fn default() -> Self {
        Self {
            kind: CurrentKind::None,
            velocity: None,
            points: None,
            surface_velocity: None,
            exponent: None,
            schedule: None,
            in_static: true,
            ramp_time: 10.0,
        }
    }
}

/// `sea.waves.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaveKind {
    /// Still water.
    #[default]
    None,
    /// Linear regular wave.
    Airy,
    /// Stokes second-order regular wave.
    Stokes2,
    /// User-listed linear components.
    Components,
    /// Irregular sea from a spectrum.
    Irregular,
}

/// `[sea.waves]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WavesSpec {
    /// Which waves.
    #[serde(default)]
    pub kind: WaveKind,
    /// Crest-to-trough height H [m] (regular).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Period T [s] (regular).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Travel direction [deg], from +x towards +y.
    #[serde(default)]
    pub direction: f64,
    /// Phase [deg].
    #[serde(default)]
    pub phase: f64,
    /// Surface stretching (default none for regular, wheeler for irregular/components).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretching: Option<Stretching>,
    /// Wave ramp [s] (0 disables).
    #[serde(default = "default_ramp")]
    pub ramp_time: f64,
    /// [a, T, direction_deg, phase_deg] per component (kind = "components").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub components: Option<Vec<[f64; 4]>>,
    /// `[sea.waves.spectrum]` (kind = "irregular").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spectrum: Option<SpectrumSpec>,
}

impl Default for WavesSpec {
    fn default() -> Self {
        Self {
            kind: WaveKind::None,
            height: None,
            period: None,
            direction: 0.0,
            phase: 0.0,
            stretching: None,
            ramp_time: 10.0,
            components: None,
            spectrum: None,
        }
    }
}

/// `sea.waves.spectrum.shape`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpectrumShape {
    /// JONSWAP (DNV form).
    #[default]
    Jonswap,
    /// Pierson–Moskowitz.
    Pm,
    /// User table.
    Table,
}

/// γ: a number ≥ 1 or "auto".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum GammaValue {
    /// γ ≥ 1.
    Number(f64),
    /// Must be "auto".
    Word(String),
}

/// `[sea.waves.spectrum]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpectrumSpec {
    /// Spectrum shape.
    #[serde(default)]
    pub shape: SpectrumShape,
    /// Hs [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hs: Option<f64>,
    /// Tp [s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tp: Option<f64>,
    /// γ (JONSWAP only; default "auto").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gamma: Option<GammaValue>,
    /// Mean travel direction [deg].
    #[serde(default)]
    pub mean_direction: f64,
    /// cos-2s exponent; omit for long-crested.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spreading_s: Option<f64>,
    /// Number of components.
    #[serde(default = "default_components")]
    pub components: usize,
    /// Frequency spacing.
    #[serde(default = "default_spacing")]
    pub spacing: Spacing,
    /// Seed of the phase generator.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Energy fraction dropped (half at each end).
    #[serde(default = "default_cutoff")]
    pub energy_cutoff: f64,
    /// Rescale to m0 = Hs²/16 over the retained band.
    #[serde(default)]
    pub normalise: bool,
    /// [[omega, S], ...] for shape = "table".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<Vec<[f64; 2]>>,
}

fn default_spacing() -> Spacing {
    Spacing::RandomInBin
}

impl Default for SpectrumSpec {
    /// JONSWAP with automatic γ and the defaults of docs/theory/environment.md#wave-spectra; hs and
    /// tp still have to be given.
    fn default() -> Self {
        Self {
            shape: SpectrumShape::Jonswap,
            hs: None,
            tp: None,
            gamma: None,
            mean_direction: 0.0,
            spreading_s: None,
            components: default_components(),
            spacing: default_spacing(),
            seed: default_seed(),
            energy_cutoff: default_cutoff(),
            normalise: false,
            table: None,
        }
    }
}

/// Options that come from the rest of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildOptions {
    /// min(0, shallowest structure node z) [m] for the irregular band weighting.
    pub z_ref: f64,
    /// Simulated duration [s], to warn when an `equal` record repeats.
    pub duration: Option<f64>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            z_ref: 0.0,
            duration: None,
        }
    }
}

/// One regular wave (or listed component) in the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegularWaveSummary {
    /// H [m].
    pub height: f64,
    /// T [s].
    pub period: f64,
    /// ω [rad/s].
    pub omega: f64,
    /// k [rad/m].
    pub wave_number: f64,
    /// L [m].
    pub wavelength: f64,
    /// c [m/s].
    pub phase_speed: f64,
    /// c_g [m/s].
    pub group_speed: f64,
    /// kh (none for infinite depth).
    pub kh: Option<f64>,
    /// H/L.
    pub steepness: f64,
    /// Ursell number H L²/h³ (none for infinite depth).
    pub ursell: Option<f64>,
    /// r₂ = (k a/4) B_η.
    pub second_order_ratio: f64,
    /// Direction [deg].
    pub direction_deg: f64,
    /// Phase [deg].
    pub phase_deg: f64,
}

/// The irregular-sea part of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IrregularSummary {
    /// "jonswap" | "pm" | "table".
    pub shape: String,
    /// Hs [m] as specified.
    pub hs: Option<f64>,
    /// Tp [s] as specified (table: from its peak).
    pub tp: f64,
    /// γ used (JONSWAP).
    pub gamma: Option<f64>,
    /// Band [rad/s].
    pub omega_lo: f64,
    /// Band [rad/s].
    pub omega_hi: f64,
    /// N.
    pub components: usize,
    /// Σ a²/2 [m²].
    pub m0_retained: f64,
    /// 4√m0 [m].
    pub hm0_retained: f64,
    /// Unweighted energy fraction outside the band.
    pub dropped_fraction: f64,
    /// 2π/Δω [s] for equal spacing.
    pub repeat_period: Option<f64>,
    /// Seed.
    pub seed: u64,
    /// Spacing.
    pub spacing: Spacing,
    /// Mean direction [deg].
    pub mean_direction_deg: f64,
    /// cos-2s exponent (none: long-crested).
    pub spreading_s: Option<f64>,
}

/// The sea-state summary printed at start-up and by `aqua waves` (SI units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeaSummary {
    /// g [m/s²].
    pub gravity: f64,
    /// ρ_w [kg/m³].
    pub density: f64,
    /// ν [m²/s].
    pub kinematic_viscosity: f64,
    /// h [m] (none = infinite or not given).
    pub depth: Option<f64>,
    /// Current kind.
    pub current: CurrentKind,
    /// Current velocity at the surface [m/s].
    pub current_surface_velocity: [f64; 3],
    /// Current ramp [s].
    pub current_ramp_time: f64,
    /// Wave kind.
    pub waves: WaveKind,
    /// Stretching in use (none for still water).
    pub stretching: Option<Stretching>,
    /// Wave ramp [s].
    pub wave_ramp_time: f64,
    /// Regular waves or listed components.
    pub regular: Vec<RegularWaveSummary>,
    /// Irregular sea.
    pub irregular: Option<IrregularSummary>,
    /// Validity and range warnings (never errors).
    pub warnings: Vec<String>,
}

fn positive(key: &str, v: f64, what: &str) -> Result<f64, EnvError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(EnvError::range(
            key,
            v,
            format!("must be a finite number > 0 ({what})"),
        ))
    }
}

fn need<T: Copy>(v: Option<T>, key: &str, why: &str) -> Result<T, EnvError> {
    v.ok_or_else(|| EnvError::missing(key, why))
}

fn unused<T>(v: &Option<T>, key: &str, used_with: &str) -> Result<(), EnvError> {
    if v.is_some() {
        Err(EnvError::range(
            key,
            "(given)",
            format!("this key is only used with {used_with}; remove it"),
        ))
    } else {
        Ok(())
    }
}

/// Every velocity of `[sea.current]` finite and at most [`MAX_CURRENT_SPEED`] in magnitude.
fn current_speeds(s: &CurrentSpec) -> Result<(), EnvError> {
    let check = |key: String, v: [f64; 3]| {
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if speed <= MAX_CURRENT_SPEED {
            Ok(())
        } else {
            Err(EnvError::range(
                key,
                format!("[{}, {}, {}] ({speed} m/s)", v[0], v[1], v[2]),
                format!(
                    "a current of finite speed up to {MAX_CURRENT_SPEED} m/s (the fastest tidal \
                     streams reach about 5 m/s)"
                ),
            ))
        }
    };
    if let Some(v) = s.velocity {
        check("sea.current.velocity".into(), v)?;
    }
    if let Some(v) = s.surface_velocity {
        check("sea.current.surface_velocity".into(), v)?;
    }
    for (j, p) in s.points.iter().flatten().enumerate() {
        check(format!("sea.current.points[{j}]"), vec3(p))?;
    }
    for (j, p) in s.schedule.iter().flatten().enumerate() {
        check(format!("sea.current.schedule[{j}]"), vec3(p))?;
    }
    Ok(())
}

fn vec3(a: &[f64; 4]) -> [f64; 3] {
    [a[1], a[2], a[3]]
}

impl SeaSpec {
    /// Parses a `[sea]` table from TOML text (the whole text is the sea table).
    pub fn from_toml(text: &str) -> Result<Self, toml::de::Error> {
        toml::from_str(text)
    }

    /// g, ρ_w, ν and the depth, validated.
    pub fn constants(&self) -> Result<Constants, EnvError> {
        let gravity = positive("sea.gravity", self.gravity, "m/s², e.g. 9.80665")?;
        let density = positive("sea.water.density", self.water.density, "kg/m³, e.g. 1025")?;
        let kinematic_viscosity = positive(
            "sea.water.kinematic_viscosity",
            self.water.kinematic_viscosity,
            "m²/s, e.g. 1.19e-6",
        )?;
        let depth = match &self.depth {
            None => Depth::Infinite,
            Some(DepthValue::Metres(h)) => Depth::Finite(positive(
                "sea.depth",
                *h,
                "water depth in m, or \"infinite\"",
            )?),
            Some(DepthValue::Word(w)) if w == "infinite" => Depth::Infinite,
            Some(DepthValue::Word(w)) => {
                return Err(EnvError::range(
                    "sea.depth",
                    format!("\"{w}\""),
                    "a water depth in m (> 0) or \"infinite\"",
                ));
            }
        };
        Ok(Constants {
            gravity,
            density,
            kinematic_viscosity,
            depth,
        })
    }

    fn build_current(&self, c: &Constants) -> Result<Current, EnvError> {
        let s = &self.current;
        if !(s.ramp_time >= 0.0 && s.ramp_time.is_finite()) {
            return Err(EnvError::range(
                "sea.current.ramp_time",
                s.ramp_time,
                "a duration in s, >= 0 (0 disables the ramp)",
            ));
        }
        let ramp = Ramp::new(s.ramp_time);
        let (velocity_for, points_for, power_for) = (
            "kind = \"uniform\"",
            "kind = \"profile\"",
            "kind = \"power_law\"",
        );
        let profile = match s.kind {
            CurrentKind::None => {
                unused(&s.velocity, "sea.current.velocity", velocity_for)?;
                unused(&s.points, "sea.current.points", points_for)?;
                unused(
                    &s.surface_velocity,
                    "sea.current.surface_velocity",
                    power_for,
                )?;
                unused(&s.schedule, "sea.current.schedule", velocity_for)?;
                return Ok(Current::none());
            }
            CurrentKind::Uniform => {
                unused(&s.points, "sea.current.points", points_for)?;
                unused(
                    &s.surface_velocity,
                    "sea.current.surface_velocity",
                    power_for,
                )?;
                unused(&s.exponent, "sea.current.exponent", power_for)?;
                match (&s.velocity, &s.schedule) {
                    (Some(v), None) => CurrentProfile::Uniform(*v),
                    (None, Some(sch)) => {
                        CurrentProfile::Uniform(sch.first().map(vec3).unwrap_or([0.0; 3]))
                    }
                    (Some(_), Some(_)) => {
                        return Err(EnvError::range(
                            "sea.current.schedule",
                            "(given with velocity)",
                            "give either velocity or schedule, not both",
                        ));
                    }
                    (None, None) => {
                        return Err(EnvError::missing(
                            "sea.current.velocity",
                            "kind = \"uniform\" needs velocity = [ux, uy, uz] (m/s) or a schedule",
                        ));
                    }
                }
            }
            CurrentKind::Profile => {
                unused(&s.velocity, "sea.current.velocity", velocity_for)?;
                unused(
                    &s.surface_velocity,
                    "sea.current.surface_velocity",
                    power_for,
                )?;
                unused(&s.exponent, "sea.current.exponent", power_for)?;
                unused(&s.schedule, "sea.current.schedule", velocity_for)?;
                let pts = s.points.as_ref().ok_or_else(|| {
                    EnvError::missing(
                        "sea.current.points",
                        "kind = \"profile\" needs points = [[z, ux, uy, uz], ...]",
                    )
                })?;
                CurrentProfile::Profile(pts.iter().map(|p| (p[0], vec3(p))).collect())
            }
            CurrentKind::PowerLaw => {
                unused(&s.velocity, "sea.current.velocity", velocity_for)?;
                unused(&s.points, "sea.current.points", points_for)?;
                unused(&s.schedule, "sea.current.schedule", velocity_for)?;
                let surface = need(
                    s.surface_velocity,
                    "sea.current.surface_velocity",
                    "kind = \"power_law\" needs surface_velocity = [ux, uy, uz] (m/s)",
                )?;
                let depth = c.depth.finite().ok_or_else(|| {
                    EnvError::missing(
                        "sea.depth",
                        "a power-law current needs a finite water depth",
                    )
                })?;
                CurrentProfile::PowerLaw {
                    surface,
                    exponent: s.exponent.unwrap_or(1.0 / 7.0),
                    depth,
                }
            }
        };
        profile.validate()?;
        current_speeds(s)?;
        let schedule = match &s.schedule {
            None => None,
            Some(steps) => {
                if steps.is_empty() {
                    return Err(EnvError::range(
                        "sea.current.schedule",
                        "[]",
                        "at least one [t_start, ux, uy, uz] entry",
                    ));
                }
                for (j, st) in steps.iter().enumerate() {
                    if !(st[0] >= 0.0) || (j > 0 && !(st[0] > steps[j - 1][0])) {
                        return Err(EnvError::range(
                            format!("sea.current.schedule[{j}] t_start"),
                            st[0],
                            "start times must be >= 0 and strictly increasing",
                        ));
                    }
                }
                Some(Schedule {
                    steps: steps.iter().map(|st| (st[0], vec3(st))).collect(),
                    blend: ramp,
                })
            }
        };
        Ok(Current {
            profile: Some(profile),
            schedule,
            in_static: s.in_static,
            ramp,
        })
    }

    /// Validates the table and builds the [`Sea`] and its summary (with warnings).
    pub fn build(&self, opts: &BuildOptions) -> Result<(Sea, SeaSummary), EnvError> {
        let c = self.constants()?;
        for (key, v) in [
            ("sea.seabed.kbot", self.seabed.kbot),
            ("sea.seabed.cbot", self.seabed.cbot),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(EnvError::range(key, v, "a finite number >= 0"));
            }
        }
        let dc = self.seabed.damping_depth;
        if !(dc > 0.0 && dc.is_finite()) {
            return Err(EnvError::range(
                "sea.seabed.damping_depth",
                dc,
                "a penetration in m, finite and > 0 (default 0.01)",
            ));
        }
        self.seabed.validate_friction()?;
        let current = self.build_current(&c)?;
        let mut warnings = Vec::new();
        let w = &self.waves;
        if !(w.ramp_time >= 0.0 && w.ramp_time.is_finite()) {
            return Err(EnvError::range(
                "sea.waves.ramp_time",
                w.ramp_time,
                "a duration in s, >= 0 (0 disables the ramp)",
            ));
        }
        let ramp = Ramp::new(w.ramp_time);
        if w.kind != WaveKind::None && self.depth.is_none() {
            return Err(EnvError::missing(
                "sea.depth",
                "waves need a water depth: give sea.depth in m, or \"infinite\" for deep water",
            ));
        }
        let regular_only = "kind = \"airy\" or \"stokes2\"";
        if !matches!(w.kind, WaveKind::Airy | WaveKind::Stokes2) {
            unused(&w.height, "sea.waves.height", regular_only)?;
            unused(&w.period, "sea.waves.period", regular_only)?;
        }
        if w.kind != WaveKind::Components {
            unused(
                &w.components,
                "sea.waves.components",
                "kind = \"components\"",
            )?;
        }
        if w.kind != WaveKind::Irregular {
            unused(&w.spectrum, "sea.waves.spectrum", "kind = \"irregular\"")?;
        }
        let direction = w.direction.to_radians();
        let phase = w.phase.to_radians();
        let mut regular = Vec::new();
        let mut irregular = None;
        let mut stretching = None;
        let waves = match w.kind {
            WaveKind::None => {
                unused(&w.stretching, "sea.waves.stretching", "waves")?;
                Waves::None
            }
            WaveKind::Airy | WaveKind::Stokes2 => {
                let h = positive(
                    "sea.waves.height",
                    need(
                        w.height,
                        "sea.waves.height",
                        "regular waves need height (m)",
                    )?,
                    "crest-to-trough height in m",
                )?;
                let t = positive(
                    "sea.waves.period",
                    need(
                        w.period,
                        "sea.waves.period",
                        "regular waves need period (s)",
                    )?,
                    "period in s",
                )?;
                let comp = Component::new(h / 2.0, t, direction, phase, c.depth, c.gravity)?;
                let st = w.stretching.unwrap_or(Stretching::None);
                stretching = Some(st);
                let stokes = Stokes2::new(comp, c.depth, c.gravity);
                let summary = regular_summary(&comp, &stokes, c.depth);
                regular_warnings(&summary, w.kind, &mut warnings);
                regular.push(summary);
                if w.kind == WaveKind::Airy {
                    Waves::Linear {
                        sum: LinearSum::new(vec![comp], c.depth, c.gravity),
                        stretching: st,
                        ramp,
                    }
                } else {
                    Waves::Stokes2 {
                        wave: stokes,
                        stretching: st,
                        ramp,
                    }
                }
            }
            WaveKind::Components => {
                let list = w.components.as_ref().ok_or_else(|| {
                    EnvError::missing(
                        "sea.waves.components",
                        "kind = \"components\" needs components = [[a, T, direction_deg, phase_deg], ...]",
                    )
                })?;
                if list.is_empty() {
                    return Err(EnvError::range(
                        "sea.waves.components",
                        "[]",
                        "at least one [a, T, direction_deg, phase_deg]",
                    ));
                }
                let mut comps = Vec::with_capacity(list.len());
                for (i, row) in list.iter().enumerate() {
                    positive(
                        &format!("sea.waves.components[{i}] a"),
                        row[0],
                        "amplitude in m",
                    )?;
                    positive(
                        &format!("sea.waves.components[{i}] T"),
                        row[1],
                        "period in s",
                    )?;
                    let comp = Component::new(
                        row[0],
                        row[1],
                        row[2].to_radians(),
                        row[3].to_radians(),
                        c.depth,
                        c.gravity,
                    )?;
                    let s =
                        regular_summary(&comp, &Stokes2::new(comp, c.depth, c.gravity), c.depth);
                    regular_warnings(&s, WaveKind::Components, &mut warnings);
                    regular.push(s);
                    comps.push(comp);
                }
                let st = w.stretching.unwrap_or(Stretching::Wheeler);
                if st == Stretching::None {
                    warnings.push(
                        "sea.waves.stretching = \"none\" with several components: high-frequency \
                         components grow without bound above z = 0; \"wheeler\" is recommended"
                            .into(),
                    );
                }
                stretching = Some(st);
                Waves::Linear {
                    sum: LinearSum::new(comps, c.depth, c.gravity),
                    stretching: st,
                    ramp,
                }
            }
            WaveKind::Irregular => {
                let sp = w.spectrum.as_ref().ok_or_else(|| {
                    EnvError::missing(
                        "sea.waves.spectrum",
                        "kind = \"irregular\" needs a [sea.waves.spectrum] table with hs and tp",
                    )
                })?;
                let (spec, summary) = irregular_spec(sp, &mut warnings)?;
                let d = discretise(&spec, c.depth, c.gravity, opts.z_ref)?;
                let st = w.stretching.unwrap_or(Stretching::Wheeler);
                if st == Stretching::None {
                    warnings.push(
                        "sea.waves.stretching = \"none\" in an irregular sea: high-frequency \
                         components grow without bound above z = 0; \"wheeler\" is recommended"
                            .into(),
                    );
                }
                if let (Some(tr), Some(dur)) = (d.repeat_period, opts.duration)
                    && dur > tr
                {
                    warnings.push(format!(
                        "spacing = \"equal\" repeats every {tr:.1} s but the run lasts {dur:.1} s; \
                         use more components or spacing = \"random_in_bin\""
                    ));
                }
                stretching = Some(st);
                irregular = Some(IrregularSummary {
                    omega_lo: d.omega_lo,
                    omega_hi: d.omega_hi,
                    components: d.components.len(),
                    m0_retained: d.m0_retained,
                    hm0_retained: 4.0 * d.m0_retained.sqrt(),
                    dropped_fraction: d.dropped_fraction,
                    repeat_period: d.repeat_period,
                    ..summary
                });
                Waves::Linear {
                    sum: LinearSum::new(d.components, c.depth, c.gravity),
                    stretching: st,
                    ramp,
                }
            }
        };
        let summary = SeaSummary {
            gravity: c.gravity,
            density: c.density,
            kinematic_viscosity: c.kinematic_viscosity,
            depth: c.depth.finite(),
            current: self.current.kind,
            current_surface_velocity: current
                .profile
                .as_ref()
                .map(|p| p.velocity(0.0))
                .unwrap_or([0.0; 3]),
            current_ramp_time: self.current.ramp_time,
            waves: w.kind,
            stretching,
            wave_ramp_time: if w.kind == WaveKind::None {
                0.0
            } else {
                w.ramp_time
            },
            regular,
            irregular,
            warnings,
        };
        Ok((Sea::new(c, current, waves), summary))
    }
}

fn regular_summary(comp: &Component, stokes: &Stokes2, depth: Depth) -> RegularWaveSummary {
    let h = 2.0 * comp.amplitude;
    let l = 2.0 * PI / comp.k;
    let dh = depth.finite();
    RegularWaveSummary {
        height: h,
        period: comp.period(),
        omega: comp.omega,
        wave_number: comp.k,
        wavelength: l,
        phase_speed: comp.omega / comp.k,
        group_speed: group_velocity(comp.omega, comp.k, depth),
        kh: dh.map(|d| comp.k * d),
        steepness: h / l,
        ursell: dh.map(|d| h * l * l / (d * d * d)),
        second_order_ratio: stokes.second_order_ratio(),
        direction_deg: comp.direction.to_degrees(),
        phase_deg: comp.phase.to_degrees(),
    }
}

fn regular_warnings(s: &RegularWaveSummary, kind: WaveKind, warnings: &mut Vec<String>) {
    let tanh_kh = s.kh.map(f64::tanh).unwrap_or(1.0);
    let miche = 0.142 * tanh_kh;
    if s.steepness > miche {
        warnings.push(format!(
            "wave H = {} m, T = {} s: steepness H/L = {:.4} exceeds the Miche breaking limit \
             0.142·tanh(kh) = {:.4}",
            s.height, s.period, s.steepness, miche
        ));
    }
    match kind {
        WaveKind::Stokes2 if s.second_order_ratio > 0.25 => warnings.push(format!(
            "stokes2 wave H = {} m, T = {} s: second-order ratio r2 = {:.3} > 1/4 (Ursell {}): \
             the profile grows a secondary crest in the trough; a higher-order theory is needed",
            s.height,
            s.period,
            s.second_order_ratio,
            s.ursell.map(|u| format!("{u:.1}")).unwrap_or("-".into())
        )),
        WaveKind::Airy | WaveKind::Components if s.second_order_ratio > 0.1 => {
            warnings.push(format!(
                "wave H = {} m, T = {} s: second-order effects are {:.0} % of the first order \
                 (r2 = {:.3} > 0.1); consider kind = \"stokes2\"",
                s.height,
                s.period,
                100.0 * s.second_order_ratio,
                s.second_order_ratio
            ))
        }
        _ => {}
    }
}

/// The JONSWAP γ where the DNV factor 1 − 0.287·ln γ reaches 0 (docs/theory/environment.md#wave-spectra).
const MAX_GAMMA: f64 = 32.6;

fn irregular_spec(
    sp: &SpectrumSpec,
    warnings: &mut Vec<String>,
) -> Result<(IrregularSpec, IrregularSummary), EnvError> {
    let key = |k: &str| format!("sea.waves.spectrum.{k}");
    let param = "shape = \"jonswap\" or \"pm\"";
    let mut gamma_used = None;
    let spectrum = match sp.shape {
        SpectrumShape::Jonswap | SpectrumShape::Pm => {
            unused(&sp.table, &key("table"), "shape = \"table\"")?;
            let hs = positive(
                &key("hs"),
                need(sp.hs, &key("hs"), "the spectrum needs hs (m)")?,
                "significant wave height in m",
            )?;
            let tp = positive(
                &key("tp"),
                need(sp.tp, &key("tp"), "the spectrum needs tp (s)")?,
                "peak period in s",
            )?;
            if sp.shape == SpectrumShape::Pm {
                unused(&sp.gamma, &key("gamma"), "shape = \"jonswap\"")?;
                Spectrum::PiersonMoskowitz { hs, tp }
            } else {
                let phi = tp / hs.sqrt();
                let gamma = match &sp.gamma {
                    None => gamma_auto(hs, tp),
                    Some(GammaValue::Word(w)) if w == "auto" => gamma_auto(hs, tp),
                    Some(GammaValue::Word(w)) => {
                        return Err(EnvError::range(
                            key("gamma"),
                            format!("\"{w}\""),
                            "a number >= 1 or \"auto\"",
                        ));
                    }
                    Some(GammaValue::Number(g)) => {
                        if !(*g >= 1.0 && *g < MAX_GAMMA) {
                            return Err(EnvError::range(
                                key("gamma"),
                                g,
                                format!(
                                    "a number >= 1 (1 is Pierson-Moskowitz) and < {MAX_GAMMA:.2} \
                                     (where the factor 1 − 0.287·ln γ stays > 0), or \"auto\""
                                ),
                            ));
                        }
                        if *g > 7.0 {
                            warnings.push(format!(
                                "{} = {g} is above 7, outside the usual JONSWAP range",
                                key("gamma")
                            ));
                        }
                        *g
                    }
                };
                if !(3.6 < phi && phi < 5.0) {
                    warnings.push(format!(
                        "Tp/sqrt(Hs) = {phi:.2} is outside DNV's JONSWAP range 3.6 < Tp/sqrt(Hs) < 5 \
                         (gamma = {gamma:.3} used)"
                    ));
                }
                gamma_used = Some(gamma);
                Spectrum::Jonswap { hs, tp, gamma }
            }
        }
        SpectrumShape::Table => {
            unused(&sp.hs, &key("hs"), param)?;
            unused(&sp.tp, &key("tp"), param)?;
            unused(&sp.gamma, &key("gamma"), "shape = \"jonswap\"")?;
            let t = sp.table.as_ref().ok_or_else(|| {
                EnvError::missing(
                    key("table"),
                    "shape = \"table\" needs table = [[omega, S], ...]",
                )
            })?;
            if t.len() < 2 {
                return Err(EnvError::range(
                    key("table"),
                    format!("{} rows", t.len()),
                    "at least two [omega, S] rows",
                ));
            }
            for (i, r) in t.iter().enumerate() {
                if !(r[0] > 0.0) || (i > 0 && !(r[0] > t[i - 1][0])) || !(r[1] >= 0.0) {
                    return Err(EnvError::range(
                        format!("{}[{i}]", key("table")),
                        format!("[{}, {}]", r[0], r[1]),
                        "omega > 0 strictly increasing (rad/s), S >= 0 (m²·s/rad)",
                    ));
                }
            }
            Spectrum::Table {
                points: t.iter().map(|r| (r[0], r[1])).collect(),
            }
        }
    };
    if let Some(s) = sp.spreading_s
        && !(s > 0.0 && s.is_finite())
    {
        return Err(EnvError::range(
            key("spreading_s"),
            s,
            "a cos-2s exponent > 0 (omit it for a long-crested sea)",
        ));
    }
    if !(1..=100_000).contains(&sp.components) {
        return Err(EnvError::range(
            key("components"),
            sp.components,
            "between 1 and 100000 (a few hundred is usual)",
        ));
    }
    if !(sp.energy_cutoff > 0.0 && sp.energy_cutoff < 1.0) {
        return Err(EnvError::range(
            key("energy_cutoff"),
            sp.energy_cutoff,
            "a fraction > 0 and < 1 (default 1e-3)",
        ));
    }
    let spec = IrregularSpec {
        spectrum: spectrum.clone(),
        mean_direction: sp.mean_direction.to_radians(),
        spreading_s: sp.spreading_s,
        components: sp.components,
        spacing: sp.spacing,
        seed: sp.seed,
        energy_cutoff: sp.energy_cutoff,
        normalise: sp.normalise,
    };
    let summary = IrregularSummary {
        shape: match sp.shape {
            SpectrumShape::Jonswap => "jonswap",
            SpectrumShape::Pm => "pm",
            SpectrumShape::Table => "table",
        }
        .into(),
        hs: spectrum.hs(),
        tp: 2.0 * PI / spectrum.peak_omega(),
        gamma: gamma_used,
        omega_lo: 0.0,
        omega_hi: 0.0,
        components: 0,
        m0_retained: 0.0,
        hm0_retained: 0.0,
        dropped_fraction: 0.0,
        repeat_period: None,
        seed: sp.seed,
        spacing: sp.spacing,
        mean_direction_deg: sp.mean_direction,
        spreading_s: sp.spreading_s,
    };
    Ok((spec, summary))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<(Sea, SeaSummary), String> {
        let spec: SeaSpec = toml::from_str(s).map_err(|e| e.to_string())?;
        spec.build(&BuildOptions::default())
            .map_err(|e| e.to_string())
    }

    #[test]
    fn spec_example_parses() {
        let (sea, sum) = parse(
            r#"
gravity = 9.80665
depth = 60.0
[water]
density = 1025.0
kinematic_viscosity = 1.19e-6
[current]
kind = "uniform"
velocity = [0.5, 0.0, 0.0]
in_static = true
ramp_time = 10.0
[waves]
kind = "airy"
height = 2.0
period = 8.0
direction = 0.0
phase = 0.0
stretching = "none"
ramp_time = 10.0
"#,
        )
        .unwrap();
        assert!(sea.has_waves() && sea.has_current());
        assert_eq!(sum.regular.len(), 1);
        assert!(sum.warnings.is_empty(), "{:?}", sum.warnings);
    }

    #[test]
    fn unknown_key_is_rejected_with_its_name() {
        let e =
            parse("depth = 10\n[waves]\nkind = \"airy\"\nheigth = 2.0\nperiod = 8\n").unwrap_err();
        assert!(e.contains("heigth"), "{e}");
    }

    #[test]
    fn bad_values_name_key_and_range() {
        let e =
            parse("depth = 10\n[waves]\nkind = \"airy\"\nheight = -2.0\nperiod = 8\n").unwrap_err();
        assert!(
            e.contains("sea.waves.height") && e.contains("-2") && e.contains("> 0"),
            "{e}"
        );
        let e = parse("[waves]\nkind = \"airy\"\nheight = 2.0\nperiod = 8\n").unwrap_err();
        assert!(e.contains("sea.depth"), "{e}");
        let e = parse("depth = 0\n").unwrap_err();
        assert!(e.contains("sea.depth"), "{e}");
        let e =
            parse("depth = 10\n[waves]\nkind = \"airy\"\nheight = 2\nperiod = 0\n").unwrap_err();
        assert!(e.contains("sea.waves.period"), "{e}");
        let e = parse("depth = 10\n[current]\nkind = \"uniform\"\n").unwrap_err();
        assert!(e.contains("sea.current.velocity"), "{e}");
    }

    #[test]
    fn stokes_validity_warnings() {
        let base = |h: f64| {
            format!(
                "gravity = 9.81\ndepth = 10\n[waves]\nkind = \"stokes2\"\nheight = {h}\nperiod = 8\n"
            )
        };
        let (_, s) = parse(&base(2.0)).unwrap();
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        let (_, s) = parse(&base(6.0)).unwrap();
        assert!(
            s.warnings.iter().any(|w| w.contains("secondary crest")),
            "{:?}",
            s.warnings
        );
    }

    #[test]
    fn spec_e5_summary_numbers() {
        let (_, s) = parse(
            "gravity = 9.81\ndepth = 20\n[waves]\nkind = \"stokes2\"\nheight = 2\nperiod = 8\n",
        )
        .unwrap();
        let r = &s.regular[0];
        assert!((r.kh.unwrap() - 1.41524857).abs() < 5e-9);
        assert!((r.ursell.unwrap() - 1.971).abs() < 5e-4);
        assert!(s.warnings.is_empty());
    }

    #[test]
    fn jonswap_outside_dnv_range_warns() {
        let (_, s) =
            parse("depth = 60\n[waves]\nkind = \"irregular\"\n[waves.spectrum]\nhs = 2\ntp = 8\n")
                .unwrap();
        assert!(s.warnings.iter().any(|w| w.contains("JONSWAP range")));
        assert_eq!(s.irregular.as_ref().unwrap().gamma, Some(1.0));
        assert_eq!(s.stretching, Some(Stretching::Wheeler));
    }
}
