//! Checks of the `[sea]` keys, with messages that name key, value and what is valid: the
//! shared checks, the fluid constants and depth, and the spectrum table.

use super::schema::{CurrentSpec, DepthValue, GammaValue, SeaSpec, SpectrumShape, SpectrumSpec};
use super::summary::IrregularSummary;
use crate::constants::{Constants, Depth};
use crate::current::MAX_CURRENT_SPEED;
use crate::error::EnvError;
use crate::irregular::IrregularSpec;
use crate::spectrum::{Spectrum, gamma_auto};
use std::f64::consts::PI;

pub(super) fn positive(key: &str, v: f64, what: &str) -> Result<f64, EnvError> {
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

/// Longest regular wave period accepted [s]: an hour (swell is under 30 s; a longer "wave" is
/// a tide or a current, and the dispersion relation has no root to find for ω → 0 in f64).
pub(super) const MAX_WAVE_PERIOD: f64 = 3600.0;

/// A regular wave's period T [s]: 0 < T ≤ [`MAX_WAVE_PERIOD`].
pub(super) fn wave_period(key: &str, v: f64) -> Result<f64, EnvError> {
    if v > 0.0 && v <= MAX_WAVE_PERIOD {
        Ok(v)
    } else {
        Err(EnvError::range(
            key,
            v,
            format!("must be a number > 0 and <= {MAX_WAVE_PERIOD} s (a wave period in s)"),
        ))
    }
}

pub(super) fn need<T: Copy>(v: Option<T>, key: &str, why: &str) -> Result<T, EnvError> {
    v.ok_or_else(|| EnvError::missing(key, why))
}

pub(super) fn unused<T>(v: &Option<T>, key: &str, used_with: &str) -> Result<(), EnvError> {
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
pub(super) fn current_speeds(s: &CurrentSpec) -> Result<(), EnvError> {
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

pub(super) fn vec3(a: &[f64; 4]) -> [f64; 3] {
    [a[1], a[2], a[3]]
}

impl SeaSpec {
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
}

/// The JONSWAP γ where the DNV factor 1 − 0.287·ln γ reaches 0 (docs/theory/environment.md#wave-spectra).
const MAX_GAMMA: f64 = 32.6;

pub(super) fn irregular_spec(
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
