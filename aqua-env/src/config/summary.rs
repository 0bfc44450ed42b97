//! The sea-state summary printed at start-up and by `aqua waves`: its types, the figures of a
//! regular wave, and the validity warnings (breaking, second order) they give.

use super::schema::CurrentKind;
use super::schema::WaveKind;
use crate::airy::Component;
use crate::constants::Depth;
use crate::dispersion::group_velocity;
use crate::irregular::Spacing;
use crate::stokes::Stokes2;
use crate::stretching::Stretching;
use serde::Serialize;
use std::f64::consts::PI;

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

pub(super) fn regular_summary(
    comp: &Component,
    stokes: &Stokes2,
    depth: Depth,
) -> RegularWaveSummary {
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

pub(super) fn regular_warnings(s: &RegularWaveSummary, kind: WaveKind, warnings: &mut Vec<String>) {
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
