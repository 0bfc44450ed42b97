//! Stokes second-order regular wave (docs/theory/environment.md#stokes-second-order-waves; Dean &
//! Dalrymple ch. 11).
//!
//! With E = e^{−2kh}:
//! η = a cos θ + (k a²/4) B_η cos 2θ, B_η = cosh kh (2 + cosh 2kh)/sinh³ kh;
//! u_h = [ωa C(z) cos θ + ¾ ω k a² C₂(z) cos 2θ] d, w = ωa S(z) sin θ + ¾ ω k a² S₂(z) sin 2θ,
//! C₂ = cosh 2k(z+h)/sinh⁴ kh, S₂ = sinh 2k(z+h)/sinh⁴ kh (→ 0 in deep water);
//! accelerations are the local time derivatives; p_d keeps the first-order term only.

use crate::airy::{Component, RawKinematics, depth_constants, depth_functions};
use crate::constants::Depth;

/// A regular Stokes second-order wave (same ω and k as the linear wave).
#[derive(Debug, Clone)]
pub struct Stokes2 {
    /// The first-order component (a = H/2).
    pub first: Component,
    depth: Depth,
    g: f64,
    b_eta: f64,
    cos_b: f64,
    sin_b: f64,
    e: f64,
    inv_m: f64,
    inv_p: f64,
}

impl Stokes2 {
    /// A Stokes-2 wave from its first-order component.
    pub fn new(first: Component, depth: Depth, g: f64) -> Self {
        let (e, inv_m, inv_p) = depth_constants(first.k, depth);
        let b_eta = match depth {
            Depth::Infinite => 2.0,
            Depth::Finite(_) => {
                let om = 1.0 / inv_m; // 1 − E
                2.0 * (1.0 + e) * (1.0 + 4.0 * e + e * e) / (om * om * om)
            }
        };
        let (sin_b, cos_b) = first.direction.sin_cos();
        Self {
            first,
            depth,
            g,
            b_eta,
            cos_b,
            sin_b,
            e,
            inv_m,
            inv_p,
        }
    }

    /// B_η = cosh kh (2 + cosh 2kh)/sinh³ kh (→ 2 in deep water).
    pub fn b_eta(&self) -> f64 {
        self.b_eta
    }

    /// Ratio of second- to first-order elevation amplitude r₂ = (k a/4) B_η.
    pub fn second_order_ratio(&self) -> f64 {
        self.first.k * self.first.amplitude / 4.0 * self.b_eta
    }

    fn theta(&self, x: f64, y: f64, t: f64) -> f64 {
        let c = &self.first;
        c.k * (x * self.cos_b + y * self.sin_b) - c.omega * t + c.phase
    }

    /// Unramped elevation η [m] at (x, y, t).
    pub fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        self.elevation_at_phase(self.theta(x, y, t))
    }

    /// η as a function of the phase θ [rad].
    pub fn elevation_at_phase(&self, th: f64) -> f64 {
        let (a, k) = (self.first.amplitude, self.first.k);
        a * th.cos() + k * a * a / 4.0 * self.b_eta * (2.0 * th).cos()
    }

    /// (C₂, S₂) at evaluation height z.
    fn second_depth(&self, z: f64) -> (f64, f64) {
        match self.depth {
            Depth::Infinite => (0.0, 0.0),
            Depth::Finite(h) => {
                if self.e == 0.0 {
                    return (0.0, 0.0);
                }
                let k = self.first.k;
                let om = 1.0 / self.inv_m;
                let base = 8.0 * (2.0 * k * (z - h)).exp() / (om * om * om * om);
                let tail = (-4.0 * k * (z + h)).exp();
                (base * (1.0 + tail), base * (1.0 - tail))
            }
        }
    }

    /// Unramped kinematics at (x, y, t) evaluated at height `zs`.
    pub(crate) fn kinematics(&self, x: f64, y: f64, t: f64, zs: f64) -> RawKinematics {
        let c = &self.first;
        let th = self.theta(x, y, t);
        let (s1, c1) = th.sin_cos();
        let (s2, c2) = (2.0 * th).sin_cos();
        let (cz, sz, kz) = depth_functions(c.k, zs, self.e, self.inv_m, self.inv_p);
        let (c2z, s2z) = self.second_depth(zs);
        let wa = c.omega * c.amplitude;
        let w2a = c.omega * wa;
        let q = 0.75 * c.omega * c.k * c.amplitude * c.amplitude;
        let qa = 1.5 * c.omega * c.omega * c.k * c.amplitude * c.amplitude;
        let uh = wa * cz * c1 + q * c2z * c2;
        let ah = w2a * cz * s1 + qa * c2z * s2;
        RawKinematics {
            vel: [
                uh * self.cos_b,
                uh * self.sin_b,
                wa * sz * s1 + q * s2z * s2,
            ],
            acc: [
                ah * self.cos_b,
                ah * self.sin_b,
                -w2a * sz * c1 - qa * s2z * c2,
            ],
            p_over_rho: self.g * c.amplitude * kz * c1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn e5() -> Stokes2 {
        let c = Component::new(1.0, 8.0, 0.0, 0.0, Depth::Finite(20.0), 9.81).unwrap();
        Stokes2::new(c, Depth::Finite(20.0), 9.81)
    }

    #[test]
    fn spec_e5_crest_and_trough() {
        let s = e5();
        assert!((s.first.k * 20.0 - 1.41524857).abs() < 5e-9);
        assert!((s.elevation_at_phase(0.0) - 1.055729655).abs() < 5e-10);
        assert!((s.elevation_at_phase(PI) + 0.9442703453).abs() < 5e-11);
    }

    #[test]
    fn b_eta_matches_hyperbolic_form() {
        let s = e5();
        let kh = s.first.k * 20.0;
        let direct = kh.cosh() * (2.0 + (2.0 * kh).cosh()) / kh.sinh().powi(3);
        assert!((s.b_eta() - direct).abs() < 1e-12 * direct);
    }

    #[test]
    fn second_order_depth_functions_match_hyperbolic_forms() {
        let s = e5();
        let (k, h) = (s.first.k, 20.0);
        for z in [-20.0, -10.0, 0.0] {
            let (c2, s2) = s.second_depth(z);
            let sh4 = (k * h).sinh().powi(4);
            assert!((c2 - (2.0 * k * (z + h)).cosh() / sh4).abs() < 1e-12);
            assert!((s2 - (2.0 * k * (z + h)).sinh() / sh4).abs() < 1e-12);
        }
    }

    #[test]
    fn deep_water_elevation_correction() {
        let c = Component::new(1.0, 8.0, 0.0, 0.0, Depth::Infinite, 9.81).unwrap();
        let s = Stokes2::new(c, Depth::Infinite, 9.81);
        let expect = 1.0 + c.k / 2.0;
        assert!((s.elevation_at_phase(0.0) - expect).abs() < 1e-14);
    }
}
