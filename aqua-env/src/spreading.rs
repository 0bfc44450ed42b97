//! Directional spreading, cos-2s (docs/theory/environment.md#directional-spreading):
//! D(Δβ) = Γ(s+1)/(2√π Γ(s+½))·cos^{2s}(Δβ/2), −π < Δβ ≤ π, ∫D dΔβ = 1.

use std::f64::consts::PI;

/// Number of points of the tabulated spreading CDF.
const TABLE_POINTS: usize = 4097;

/// The cos-2s spreading function with its tabulated inverse CDF.
#[derive(Debug, Clone)]
pub struct Cos2s {
    s: f64,
    norm: f64,
    /// Δβ at the table points and the normalised CDF there.
    beta: Vec<f64>,
    cdf: Vec<f64>,
}

impl Cos2s {
    /// Spreading exponent s > 0 (larger = narrower).
    pub fn new(s: f64) -> Self {
        let norm = (libm::lgamma(s + 1.0) - libm::lgamma(s + 0.5)).exp() / (2.0 * PI.sqrt());
        let mut beta = Vec::with_capacity(TABLE_POINTS);
        let mut cdf = Vec::with_capacity(TABLE_POINTS);
        let h = 2.0 * PI / (TABLE_POINTS - 1) as f64;
        let mut acc = 0.0;
        let mut prev = 0.0;
        for i in 0..TABLE_POINTS {
            let b = -PI + i as f64 * h;
            let d = norm * (0.5 * b).cos().max(0.0).powf(2.0 * s);
            if i > 0 {
                acc += 0.5 * (prev + d) * h;
            }
            prev = d;
            beta.push(b);
            cdf.push(acc);
        }
        let total = acc;
        for c in &mut cdf {
            *c /= total;
        }
        Self { s, norm, beta, cdf }
    }

    /// The exponent s.
    pub fn s(&self) -> f64 {
        self.s
    }

    /// The normalising constant Γ(s+1)/(2√π Γ(s+½)).
    pub fn normalising_constant(&self) -> f64 {
        self.norm
    }

    /// D(Δβ) [1/rad].
    pub fn density(&self, dbeta: f64) -> f64 {
        self.norm * (0.5 * dbeta).cos().max(0.0).powf(2.0 * self.s)
    }

    /// The inverse CDF: Δβ [rad] such that P(Δ ≤ Δβ) = v, linear in the table.
    pub fn inverse_cdf(&self, v: f64) -> f64 {
        let v = v.clamp(0.0, 1.0);
        let j = self.cdf.partition_point(|&c| c < v);
        if j == 0 {
            return self.beta[0];
        }
        if j >= self.cdf.len() {
            return self.beta[self.beta.len() - 1];
        }
        let (c0, c1) = (self.cdf[j - 1], self.cdf[j]);
        let (b0, b1) = (self.beta[j - 1], self.beta[j]);
        if c1 > c0 {
            b0 + (b1 - b0) * (v - c0) / (c1 - c0)
        } else {
            b0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::adaptive_simpson;

    #[test]
    fn spec_e10_normalisation() {
        let d = Cos2s::new(10.0);
        assert!((d.normalising_constant() - 0.9032781269).abs() < 5e-11);
        let integral = adaptive_simpson(&|b| d.density(b), -PI, PI, 1e-13, 50);
        assert!((integral - 1.0).abs() < 1e-9, "{integral}");
    }

    #[test]
    fn inverse_cdf_is_symmetric_and_monotone() {
        let d = Cos2s::new(4.0);
        assert!(d.inverse_cdf(0.5).abs() < 1e-9);
        let mut last = -PI;
        for i in 1..100 {
            let v = i as f64 / 100.0;
            let b = d.inverse_cdf(v);
            assert!(b >= last);
            last = b;
            assert!((d.inverse_cdf(1.0 - v) + b).abs() < 1e-6);
        }
    }
}
