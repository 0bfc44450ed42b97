//! The `[sea]` table's schema (docs/guide/scene.md#sea): the serde types with the binding key
//! names and every default of the sea's keys. `[sea.seabed]`, the structure's contact with the
//! bed, is not the sea's: the scene reader (aqua-sim) splits it off before this type sees it.

use crate::constants::{SEA_WATER_DENSITY, SEA_WATER_VISCOSITY, STANDARD_GRAVITY};
use crate::irregular::Spacing;
use crate::stretching::Stretching;
use serde::{Deserialize, Serialize};

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
}

impl Default for SeaSpec {
    fn default() -> Self {
        Self {
            gravity: STANDARD_GRAVITY,
            depth: None,
            water: WaterSpec::default(),
            current: CurrentSpec::default(),
            waves: WavesSpec::default(),
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
            ramp_time: default_ramp(),
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
            ramp_time: default_ramp(),
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

impl SeaSpec {
    /// Parses a `[sea]` table from TOML text (the whole text is the sea table).
    pub fn from_toml(text: &str) -> Result<Self, toml::de::Error> {
        toml::from_str(text)
    }
}
