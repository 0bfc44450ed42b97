//! Discretising a spectrum into Airy components
//! (docs/theory/environment.md#choosing-the-frequency-band, #frequency-spacing,
//! #phases-and-directions).
//!
//! 1. Band [ω_lo, ω_hi] from an energy cut-off on the spectrum weighted by
//!    G(ω)² = C(z_ref)²/C(0)² (C from `airy`), on a fine trapezoid grid.
//! 2. Frequencies and amplitudes by one of three spacings (equal, random in bin, equal energy).
//! 3. Phases φ_i = 2π p_i, directions β̄ + D⁻¹(v_i) (cos-2s) or β̄.
//! 4. k_i from the exact dispersion relation.
//!
//! Random numbers come from [`SplitMix64`], drawn (u_i, p_i, v_i) for i = 0..N−1 in order.

use crate::airy::{Component, c_of_z};
use crate::constants::Depth;
use crate::dispersion::wave_number;
use crate::error::EnvError;
use crate::random::SplitMix64;
use crate::spectrum::Spectrum;
use crate::spreading::Cos2s;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Grid points used to locate the band and invert the cumulative spectrum.
const GRID: usize = 40_001;

/// How component frequencies are chosen in the band.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    /// ω_i = (n₀ + i)Δω: repeats every 2π/Δω.
    Equal,
    /// ω_i = ω_lo + (i + u_i)Δω: never repeats.
    RandomInBin,
    /// Equal energy per component, ω_i = F⁻¹((i + u_i)/N).
    EqualEnergy,
}

/// Everything that defines an irregular sea's component set.
#[derive(Debug, Clone)]
pub struct IrregularSpec {
    /// The spectrum.
    pub spectrum: Spectrum,
    /// Mean travel direction β̄ [rad].
    pub mean_direction: f64,
    /// cos-2s exponent; `None` for a long-crested sea.
    pub spreading_s: Option<f64>,
    /// Number of components N.
    pub components: usize,
    /// Frequency spacing.
    pub spacing: Spacing,
    /// Seed of the generator.
    pub seed: u64,
    /// Fraction of (weighted) energy dropped, half at each end of the band.
    pub energy_cutoff: f64,
    /// Rescale S so that the retained band has m0 = Hs²/16 exactly.
    pub normalise: bool,
}

/// The result of discretising a spectrum.
#[derive(Debug, Clone, Serialize)]
pub struct Discretisation {
    /// The components in increasing frequency (summation order).
    pub components: Vec<Component>,
    /// Lower band limit ω_lo [rad/s].
    pub omega_lo: f64,
    /// Upper band limit ω_hi [rad/s].
    pub omega_hi: f64,
    /// Bin width Δω = (ω_hi − ω_lo)/N [rad/s].
    pub d_omega: f64,
    /// Σ a_i²/2: the variance of η the component set really has [m²].
    pub m0_retained: f64,
    /// Unweighted energy fraction of the spectrum outside the band.
    pub dropped_fraction: f64,
    /// The factor S was scaled by (1 unless `normalise`).
    pub scale: f64,
    /// Repeat period 2π/Δω [s] of `equal` spacing (none otherwise).
    pub repeat_period: Option<f64>,
}

/// Cumulative trapezoid integral of y over x (same length), starting at 0.
fn cumulative(x: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(x.len());
    let mut acc = 0.0;
    out.push(0.0);
    for i in 1..x.len() {
        acc += 0.5 * (y[i] + y[i - 1]) * (x[i] - x[i - 1]);
        out.push(acc);
    }
    out
}

/// x where the monotone cumulative `c` reaches `target` (linear interpolation).
fn invert(x: &[f64], c: &[f64], target: f64) -> f64 {
    let j = c.partition_point(|&v| v < target);
    if j == 0 {
        return x[0];
    }
    if j >= c.len() {
        return x[x.len() - 1];
    }
    let (c0, c1) = (c[j - 1], c[j]);
    if c1 > c0 {
        x[j - 1] + (x[j] - x[j - 1]) * (target - c0) / (c1 - c0)
    } else {
        x[j - 1]
    }
}

/// The scene keys of a spectrum, for messages (`{ hs = 2, tp = 8, gamma = 3.3 }`).
fn keys_of(sp: &Spectrum) -> String {
    match sp {
        Spectrum::PiersonMoskowitz { hs, tp } => format!("{{ hs = {hs}, tp = {tp} }}"),
        Spectrum::Jonswap { hs, tp, gamma } => {
            format!("{{ hs = {hs}, tp = {tp}, gamma = {gamma} }}")
        }
        Spectrum::Table { points } => format!("{{ table = ({} rows) }}", points.len()),
    }
}

/// Builds the component set of an irregular sea.
///
/// `z_ref` [m] is min(0, shallowest structure node): deeper structures see less of the high
/// frequencies, so the band is chosen on the spectrum weighted by the kinematics there.
pub fn discretise(
    spec: &IrregularSpec,
    depth: Depth,
    g: f64,
    z_ref: f64,
) -> Result<Discretisation, EnvError> {
    let n = spec.components;
    let sp = &spec.spectrum;
    let (w_min, w_max) = sp.support();
    let grid: Vec<f64> = (0..GRID)
        .map(|i| w_min + (w_max - w_min) * i as f64 / (GRID - 1) as f64)
        .collect();
    let s_grid: Vec<f64> = grid.iter().map(|&w| sp.density(w)).collect();
    let z_ref = z_ref.min(0.0);
    let weighted: Vec<f64> = if z_ref < 0.0 {
        let mut out = Vec::with_capacity(GRID);
        for (&w, &s) in grid.iter().zip(&s_grid) {
            if w <= 0.0 || s == 0.0 {
                out.push(0.0);
                continue;
            }
            let k = wave_number(w, depth, g)?;
            let ratio = c_of_z(k, z_ref, depth) / c_of_z(k, 0.0, depth);
            out.push(s * ratio * ratio);
        }
        out
    } else {
        s_grid.clone()
    };
    let cum_w = cumulative(&grid, &weighted);
    let tail = sp.tail_energy();
    let tail_weighted = if z_ref < 0.0 { 0.0 } else { tail };
    let total_w = cum_w[GRID - 1] + tail_weighted;
    if !(total_w > 0.0 && total_w.is_finite()) {
        return Err(EnvError::range(
            "sea.waves.spectrum",
            keys_of(sp),
            format!(
                "its energy is {}: a spectrum with finite, positive energy (hs in m, tp in s)",
                if total_w > 0.0 { "not finite" } else { "zero" }
            ),
        ));
    }
    let half = 0.5 * spec.energy_cutoff * total_w;
    let w_lo = invert(&grid, &cum_w, half);
    let w_hi = invert(&grid, &cum_w, total_w - half).max(w_lo * (1.0 + 1e-9));

    // Unweighted energies: total, and inside the band.
    let cum_s = cumulative(&grid, &s_grid);
    let total_s = cum_s[GRID - 1] + tail;
    let band_energy = |a: f64, b: f64| -> f64 {
        let ia = interp(&grid, &cum_s, a);
        let ib = interp(&grid, &cum_s, b);
        ib - ia
    };
    let m0_band = band_energy(w_lo, w_hi);
    let dropped_fraction = ((total_s - m0_band) / total_s).max(0.0);
    let scale = if spec.normalise {
        let hs = sp.hs().ok_or_else(|| {
            EnvError::range(
                "sea.waves.spectrum.normalise",
                "true",
                "normalise needs a spectrum with hs (jonswap or pm), not a table",
            )
        })?;
        hs * hs / 16.0 / m0_band
    } else {
        1.0
    };

    let d_omega = (w_hi - w_lo) / n as f64;
    let spreading = spec.spreading_s.map(Cos2s::new);
    let mut rng = SplitMix64::new(spec.seed);
    let mut draws = Vec::with_capacity(n);
    for _ in 0..n {
        let u = rng.next_f64();
        let p = rng.next_f64();
        let v = rng.next_f64();
        draws.push((u, p, v));
    }

    // Equal-energy inversion table over the band (unweighted spectrum).
    let (band_grid, band_cdf) = if spec.spacing == Spacing::EqualEnergy {
        let m = 20_001;
        let x: Vec<f64> = (0..m)
            .map(|i| w_lo + (w_hi - w_lo) * i as f64 / (m - 1) as f64)
            .collect();
        let y: Vec<f64> = x.iter().map(|&w| sp.density(w)).collect();
        let mut c = cumulative(&x, &y);
        let last = c[m - 1];
        for v in &mut c {
            *v /= last;
        }
        (x, c)
    } else {
        (Vec::new(), Vec::new())
    };
    let n0 = ((w_lo / d_omega).round() as i64).max(1) as f64;

    let mut components = Vec::with_capacity(n);
    for (i, &(u, p, v)) in draws.iter().enumerate() {
        let (omega, amplitude) = match spec.spacing {
            Spacing::Equal => {
                let w = (n0 + i as f64) * d_omega;
                (w, (2.0 * scale * sp.density(w) * d_omega).sqrt())
            }
            Spacing::RandomInBin => {
                let w = w_lo + (i as f64 + u) * d_omega;
                (w, (2.0 * scale * sp.density(w) * d_omega).sqrt())
            }
            Spacing::EqualEnergy => {
                let w = invert(&band_grid, &band_cdf, (i as f64 + u) / n as f64);
                (w, (2.0 * scale * m0_band / n as f64).sqrt())
            }
        };
        let direction =
            spec.mean_direction + spreading.as_ref().map(|d| d.inverse_cdf(v)).unwrap_or(0.0);
        let k = wave_number(omega, depth, g)?;
        components.push(Component {
            amplitude,
            omega,
            k,
            direction,
            phase: 2.0 * PI * p,
        });
    }
    let m0_retained = components
        .iter()
        .map(|c| 0.5 * c.amplitude * c.amplitude)
        .sum();
    Ok(Discretisation {
        components,
        omega_lo: w_lo,
        omega_hi: w_hi,
        d_omega,
        m0_retained,
        dropped_fraction,
        scale,
        repeat_period: (spec.spacing == Spacing::Equal).then(|| 2.0 * PI / d_omega),
    })
}

/// Linear interpolation of y(x) at xq (clamped).
fn interp(x: &[f64], y: &[f64], xq: f64) -> f64 {
    let j = x.partition_point(|&v| v < xq);
    if j == 0 {
        return y[0];
    }
    if j >= x.len() {
        return y[y.len() - 1];
    }
    let t = (xq - x[j - 1]) / (x[j] - x[j - 1]);
    y[j - 1] + t * (y[j] - y[j - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(spacing: Spacing, seed: u64) -> IrregularSpec {
        IrregularSpec {
            spectrum: Spectrum::Jonswap {
                hs: 2.0,
                tp: 8.0,
                gamma: 3.3,
            },
            mean_direction: 0.0,
            spreading_s: None,
            components: 200,
            spacing,
            seed,
            energy_cutoff: 1e-3,
            normalise: false,
        }
    }

    #[test]
    fn band_drops_the_requested_energy() {
        let d = discretise(
            &spec(Spacing::RandomInBin, 1),
            Depth::Finite(60.0),
            9.81,
            0.0,
        )
        .unwrap();
        assert!(
            (d.dropped_fraction - 1e-3).abs() < 2e-5,
            "{}",
            d.dropped_fraction
        );
        assert!(d.omega_lo < 2.0 * PI / 8.0 && d.omega_hi > 2.0 * PI / 8.0);
        // retained variance ≈ the band energy (random-in-bin quadrature of S)
        let m0 = Spectrum::Jonswap {
            hs: 2.0,
            tp: 8.0,
            gamma: 3.3,
        }
        .m0();
        assert!((d.m0_retained / (m0 * (1.0 - 1e-3)) - 1.0).abs() < 0.03);
    }

    #[test]
    fn normalise_gives_hs_squared_over_16() {
        let mut s = spec(Spacing::EqualEnergy, 3);
        s.normalise = true;
        let d = discretise(&s, Depth::Finite(60.0), 9.81, 0.0).unwrap();
        assert!((d.m0_retained - 0.25).abs() < 1e-12);
    }

    #[test]
    fn deep_structure_narrows_the_band() {
        let s = spec(Spacing::RandomInBin, 1);
        let top = discretise(&s, Depth::Finite(60.0), 9.81, 0.0).unwrap();
        let deep = discretise(&s, Depth::Finite(60.0), 9.81, -20.0).unwrap();
        assert!(deep.omega_hi < top.omega_hi);
    }

    #[test]
    fn same_seed_same_table_different_seed_different_phases() {
        let a = discretise(&spec(Spacing::RandomInBin, 7), Depth::Infinite, 9.81, 0.0).unwrap();
        let b = discretise(&spec(Spacing::RandomInBin, 7), Depth::Infinite, 9.81, 0.0).unwrap();
        let c = discretise(&spec(Spacing::RandomInBin, 8), Depth::Infinite, 9.81, 0.0).unwrap();
        for (x, y) in a.components.iter().zip(&b.components) {
            assert_eq!(x.omega.to_bits(), y.omega.to_bits());
            assert_eq!(x.phase.to_bits(), y.phase.to_bits());
            assert_eq!(x.amplitude.to_bits(), y.amplitude.to_bits());
        }
        for (x, y) in a.components.iter().zip(&c.components) {
            assert_ne!(x.phase, y.phase);
        }
    }

    #[test]
    fn equal_spacing_frequencies_are_multiples() {
        let d = discretise(&spec(Spacing::Equal, 1), Depth::Infinite, 9.81, 0.0).unwrap();
        for c in &d.components {
            let m = c.omega / d.d_omega;
            assert!((m - m.round()).abs() < 1e-9);
        }
        assert!(d.repeat_period.is_some());
    }
}
