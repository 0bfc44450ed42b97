//! Construction of the [`Sea`] from a checked `[sea]` table: the current, the waves, and the
//! summary with its warnings.

use super::schema::{CurrentKind, SeaSpec, WaveKind};
use super::summary::{IrregularSummary, SeaSummary, regular_summary, regular_warnings};
use super::validate::{current_speeds, irregular_spec, need, positive, unused, vec3, wave_period};
use crate::airy::{Component, LinearSum};
use crate::constants::Constants;
use crate::current::{Current, CurrentProfile, Schedule};
use crate::error::EnvError;
use crate::irregular::discretise;
use crate::ramp::Ramp;
use crate::sea::{Sea, Waves};
use crate::stokes::Stokes2;
use crate::stretching::Stretching;

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

impl SeaSpec {
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
                let t = wave_period(
                    "sea.waves.period",
                    need(
                        w.period,
                        "sea.waves.period",
                        "regular waves need period (s)",
                    )?,
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
