//! Wave spectra S(ω) [m²·s/rad] (docs/theory/environment.md#wave-spectra,
//! DNV-RP-C205 §3.5.5).
//!
//! Pierson–Moskowitz: S_PM(ω) = (5/16) Hs² ω_p⁴ ω⁻⁵ exp(−(5/4)(ω/ω_p)⁻⁴);
//! JONSWAP: S_J(ω) = (1 − 0.287 ln γ) S_PM(ω) γ^{exp(−(ω−ω_p)²/(2σ²ω_p²))},
//! σ = 0.07 (ω ≤ ω_p) or 0.09 (ω > ω_p); ω_p = 2π/T_p.

use serde::Serialize;
use std::f64::consts::PI;

/// A one-sided wave spectrum.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Spectrum {
    /// JONSWAP with peak enhancement γ ≥ 1 (DNV form with the 1 − 0.287 ln γ factor).
    Jonswap {
        /// Significant wave height Hs [m].
        hs: f64,
        /// Peak period Tp [s].
        tp: f64,
        /// Peak enhancement factor γ.
        gamma: f64,
    },
    /// Pierson–Moskowitz.
    #[serde(rename = "pm")]
    PiersonMoskowitz {
        /// Significant wave height Hs [m].
        hs: f64,
        /// Peak period Tp [s].
        tp: f64,
    },
    /// User table (ω_i [rad/s], S_i [m²·s/rad]), ω increasing, linear in between, zero outside.
    Table {
        /// The points.
        points: Vec<(f64, f64)>,
    },
}

/// DNV's automatic γ from φ = T_p/√Hs: 5 for φ ≤ 3.6, exp(5.75 − 1.15φ) for 3.6 < φ < 5,
/// 1 for φ ≥ 5.
pub fn gamma_auto(hs: f64, tp: f64) -> f64 {
    let phi = tp / hs.sqrt();
    if phi <= 3.6 {
        5.0
    } else if phi < 5.0 {
        (5.75 - 1.15 * phi).exp()
    } else {
        1.0
    }
}

fn pierson_moskowitz(hs: f64, wp: f64, w: f64) -> f64 {
    if w <= 0.0 {
        return 0.0;
    }
    let r = wp / w;
    let r4 = r * r * r * r;
    let arg = -1.25 * r4;
    if arg < -745.0 {
        return 0.0;
    }
    5.0 / 16.0 * hs * hs * wp.powi(4) / w.powi(5) * arg.exp()
}

impl Spectrum {
    /// S(ω) [m²·s/rad] at ω [rad/s].
    pub fn density(&self, w: f64) -> f64 {
        match self {
            Spectrum::PiersonMoskowitz { hs, tp } => pierson_moskowitz(*hs, 2.0 * PI / tp, w),
            Spectrum::Jonswap { hs, tp, gamma } => {
                let wp = 2.0 * PI / tp;
                let pm = pierson_moskowitz(*hs, wp, w);
                if pm == 0.0 {
                    return 0.0;
                }
                let sigma = if w <= wp { 0.07 } else { 0.09 };
                let d = (w - wp) / (sigma * wp);
                (1.0 - 0.287 * gamma.ln()) * pm * gamma.powf((-0.5 * d * d).exp())
            }
            Spectrum::Table { points } => {
                if points.is_empty() || w < points[0].0 || w > points[points.len() - 1].0 {
                    return 0.0;
                }
                let j = points.partition_point(|p| p.0 <= w);
                if j == 0 {
                    return points[0].1;
                }
                if j >= points.len() {
                    return points[points.len() - 1].1;
                }
                let (w0, s0) = points[j - 1];
                let (w1, s1) = points[j];
                s0 + (s1 - s0) * (w - w0) / (w1 - w0)
            }
        }
    }

    /// Peak angular frequency ω_p [rad/s] (for a table: the ω of the largest S).
    pub fn peak_omega(&self) -> f64 {
        match self {
            Spectrum::Jonswap { tp, .. } | Spectrum::PiersonMoskowitz { tp, .. } => 2.0 * PI / tp,
            Spectrum::Table { points } => {
                points
                    .iter()
                    .fold((0.0, f64::MIN), |b, p| if p.1 > b.1 { *p } else { b })
                    .0
            }
        }
    }

    /// The significant wave height the spectrum was specified with (none for a table).
    pub fn hs(&self) -> Option<f64> {
        match self {
            Spectrum::Jonswap { hs, .. } | Spectrum::PiersonMoskowitz { hs, .. } => Some(*hs),
            Spectrum::Table { .. } => None,
        }
    }

    /// The range of ω [rad/s] over which S is tabulated for discretisation: (0, 30 ω_p] for
    /// the parametric spectra, the table's own range otherwise.
    pub fn support(&self) -> (f64, f64) {
        match self {
            Spectrum::Table { points } => (points[0].0, points[points.len() - 1].0),
            _ => (0.0, 30.0 * self.peak_omega()),
        }
    }

    /// The energy above the upper end of [`Self::support`] (∫ S dω from ω_max to ∞), from the
    /// ω⁻⁵ tail: S(ω_max)·ω_max/4 (zero for a table).
    pub fn tail_energy(&self) -> f64 {
        match self {
            Spectrum::Table { .. } => 0.0,
            _ => {
                let wm = self.support().1;
                self.density(wm) * wm / 4.0
            }
        }
    }

    /// Zeroth moment m0 = ∫₀^∞ S dω [m²] by adaptive Simpson quadrature, split at ω_p
    /// (the tail is mapped onto (0, 1] by ω = ω_p/s).
    pub fn m0(&self) -> f64 {
        match self {
            Spectrum::Table { points } => points
                .windows(2)
                .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
                .sum(),
            _ => {
                let wp = self.peak_omega();
                let lower = adaptive_simpson(&|w| self.density(w), 0.0, wp, 1e-13, 50);
                let upper = adaptive_simpson(
                    &|s: f64| {
                        if s <= 0.0 {
                            0.0
                        } else {
                            self.density(wp / s) * wp / (s * s)
                        }
                    },
                    0.0,
                    1.0,
                    1e-13,
                    50,
                );
                lower + upper
            }
        }
    }
}

/// Adaptive Simpson quadrature of f over [a, b] to absolute tolerance `tol`.
pub fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
    fn rec(
        f: &dyn Fn(f64) -> f64,
        a: f64,
        b: f64,
        fa: f64,
        fm: f64,
        fb: f64,
        whole: f64,
        tol: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        let delta = left + right - whole;
        if depth == 0 || delta.abs() <= 15.0 * tol {
            left + right + delta / 15.0
        } else {
            rec(f, a, m, fa, flm, fm, left, tol / 2.0, depth - 1)
                + rec(f, m, b, fm, frm, fb, right, tol / 2.0, depth - 1)
        }
    }
    // Start from 16 panels so narrow peaks are not missed by the first estimate.
    let n = 16;
    let h = (b - a) / n as f64;
    (0..n)
        .map(|i| {
            let (x0, x1) = (a + i as f64 * h, a + (i + 1) as f64 * h);
            let (f0, fm, f1) = (f(x0), f(0.5 * (x0 + x1)), f(x1));
            let whole = (x1 - x0) / 6.0 * (f0 + 4.0 * fm + f1);
            rec(f, x0, x1, f0, fm, f1, whole, tol / n as f64, depth)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn spec_e6_jonswap_values() {
        let s = Spectrum::Jonswap {
            hs: 2.0,
            tp: 8.0,
            gamma: 3.3,
        };
        assert!(rel(s.density(0.6), 1.0285145610e-01) < 5e-11);
        assert!(rel(s.density(2.0 * PI / 8.0), 9.8914244569e-01) < 5e-11);
        assert!(rel(s.density(1.0), 1.9663734350e-01) < 5e-11);
        assert!(rel(s.density(2.0), 9.4842327401e-03) < 5e-11);
    }

    #[test]
    fn spec_e7_m0_normalisation() {
        let s = Spectrum::Jonswap {
            hs: 2.0,
            tp: 8.0,
            gamma: 3.3,
        };
        let ratio = s.m0() / (4.0 / 16.0);
        assert!((ratio - 1.0024162).abs() < 1e-6, "{ratio}");
    }

    #[test]
    fn pm_m0_is_exact() {
        // ∫ S_PM = Hs²/16 analytically.
        let s = Spectrum::PiersonMoskowitz { hs: 3.0, tp: 10.0 };
        assert!(rel(s.m0(), 9.0 / 16.0) < 1e-9);
        // γ = 1 JONSWAP is PM.
        let j = Spectrum::Jonswap {
            hs: 3.0,
            tp: 10.0,
            gamma: 1.0,
        };
        assert_eq!(j.density(0.7), s.density(0.7));
    }

    #[test]
    fn spec_e8_gamma_auto() {
        assert!((gamma_auto(4.0, 9.0) - 1.777130527).abs() < 5e-10);
        assert_eq!(gamma_auto(2.0, 8.0), 1.0);
        assert_eq!(gamma_auto(9.0, 9.0), 5.0);
    }

    #[test]
    fn table_interpolates_and_is_zero_outside() {
        let t = Spectrum::Table {
            points: vec![(0.5, 0.0), (1.0, 2.0), (1.5, 0.0)],
        };
        assert_eq!(t.density(0.4), 0.0);
        assert_eq!(t.density(0.75), 1.0);
        assert_eq!(t.density(1.0), 2.0);
        assert_eq!(t.density(1.6), 0.0);
        assert!((t.m0() - 1.0).abs() < 1e-15);
        assert_eq!(t.peak_omega(), 1.0);
    }
}
