//! Linear (Airy) wave components and their sum (docs/theory/environment.md#airy-waves, #summation).
//!
//! A component i has amplitude a_i, angular frequency ω_i, wave number k_i, travel direction β_i
//! and phase φ_i; with θ_i = k_i(x cos β_i + y sin β_i) − ω_i t + φ_i:
//! η = a cos θ, u_h = ωa C(z) cos θ d, w = ωa S(z) sin θ, ∂u_h/∂t = ω²a C(z) sin θ d,
//! ∂w/∂t = −ω²a S(z) cos θ, p_d = ρ g a K(z) cos θ, where
//! C = cosh k(z+h)/sinh kh, S = sinh k(z+h)/sinh kh, K = cosh k(z+h)/cosh kh, all written in
//! the overflow-free form (e^{kz} ± e^{−k(z+2h)})/(1 ∓ e^{−2kh}) that tends to e^{kz} as h → ∞.

use crate::constants::Depth;
use crate::dispersion::wave_number;
use crate::error::EnvError;
use serde::Serialize;

/// Below this e^{−2kh} is treated as zero (deep water); keeps e^{−k(z+2h)} = E/e^{kz} finite.
const DEEP_E: f64 = 1e-300;

/// One linear wave component (angles in radians inside the code).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Component {
    /// Amplitude a [m].
    pub amplitude: f64,
    /// Angular frequency ω [rad/s].
    pub omega: f64,
    /// Wave number k [rad/m].
    pub k: f64,
    /// Travel direction β [rad], from +x towards +y.
    pub direction: f64,
    /// Phase φ [rad].
    pub phase: f64,
}

impl Component {
    /// A component from amplitude [m], period [s], direction [rad] and phase [rad], with k from
    /// the exact dispersion relation.
    pub fn new(
        amplitude: f64,
        period: f64,
        direction: f64,
        phase: f64,
        depth: Depth,
        g: f64,
    ) -> Result<Self, EnvError> {
        let omega = 2.0 * std::f64::consts::PI / period;
        let k = wave_number(omega, depth, g)?;
        Ok(Self {
            amplitude,
            omega,
            k,
            direction,
            phase,
        })
    }

    /// Period T = 2π/ω [s].
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
}

/// The depth functions (C, S, K) at evaluation height z for wave number k.
///
/// `e` is e^{−2kh} (0 for deep water), `inv_m` = 1/(1 − e), `inv_p` = 1/(1 + e).
#[inline(always)]
pub(crate) fn depth_functions(k: f64, z: f64, e: f64, inv_m: f64, inv_p: f64) -> (f64, f64, f64) {
    let ez = (k * z).exp();
    let second = if e == 0.0 { 0.0 } else { e / ez };
    (
        (ez + second) * inv_m,
        (ez - second) * inv_m,
        (ez + second) * inv_p,
    )
}

/// The constants (E, 1/(1 − E), 1/(1 + E)) of one wave number.
pub(crate) fn depth_constants(k: f64, depth: Depth) -> (f64, f64, f64) {
    match depth {
        Depth::Infinite => (0.0, 1.0, 1.0),
        Depth::Finite(h) => {
            let e = (-2.0 * k * h).exp();
            if e < DEEP_E {
                (0.0, 1.0, 1.0)
            } else {
                (e, -1.0 / (-2.0 * k * h).exp_m1(), 1.0 / (1.0 + e))
            }
        }
    }
}

/// cosh k(z+h)/sinh kh — the horizontal-velocity depth function C(z), public for tests and
/// for the band weighting of irregular seas.
pub fn c_of_z(k: f64, z: f64, depth: Depth) -> f64 {
    let (e, im, ip) = depth_constants(k, depth);
    depth_functions(k, z, e, im, ip).0
}

/// Wave kinematics before the ramp, at one point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct RawKinematics {
    pub vel: [f64; 3],
    pub acc: [f64; 3],
    /// p_d / ρ_w [m²/s²].
    pub p_over_rho: f64,
}

/// A sum of linear components stored as structure-of-arrays for fast evaluation.
#[derive(Debug, Clone)]
pub struct LinearSum {
    components: Vec<Component>,
    kx: Vec<f64>,
    ky: Vec<f64>,
    k: Vec<f64>,
    omega: Vec<f64>,
    phase: Vec<f64>,
    amp: Vec<f64>,
    cos_b: Vec<f64>,
    sin_b: Vec<f64>,
    e: Vec<f64>,
    inv_m: Vec<f64>,
    inv_p: Vec<f64>,
    depth: Depth,
    g: f64,
}

impl LinearSum {
    /// Builds the sum; `g` is used for the dynamic pressure ρ g a K cos θ.
    pub fn new(components: Vec<Component>, depth: Depth, g: f64) -> Self {
        let n = components.len();
        let mut s = Self {
            kx: Vec::with_capacity(n),
            ky: Vec::with_capacity(n),
            k: Vec::with_capacity(n),
            omega: Vec::with_capacity(n),
            phase: Vec::with_capacity(n),
            amp: Vec::with_capacity(n),
            cos_b: Vec::with_capacity(n),
            sin_b: Vec::with_capacity(n),
            e: Vec::with_capacity(n),
            inv_m: Vec::with_capacity(n),
            inv_p: Vec::with_capacity(n),
            components,
            depth,
            g,
        };
        for c in &s.components {
            let (sb, cb) = c.direction.sin_cos();
            let (e, im, ip) = depth_constants(c.k, depth);
            s.kx.push(c.k * cb);
            s.ky.push(c.k * sb);
            s.k.push(c.k);
            s.omega.push(c.omega);
            s.phase.push(c.phase);
            s.amp.push(c.amplitude);
            s.cos_b.push(cb);
            s.sin_b.push(sb);
            s.e.push(e);
            s.inv_m.push(im);
            s.inv_p.push(ip);
        }
        s
    }

    /// The components, in increasing summation order.
    pub fn components(&self) -> &[Component] {
        &self.components
    }

    /// The water depth the wave numbers were computed for.
    pub fn depth(&self) -> Depth {
        self.depth
    }

    /// Number of components.
    pub fn len(&self) -> usize {
        self.components.len()
    }

    /// True if there is no component.
    pub fn is_empty(&self) -> bool {
        self.components.is_empty()
    }

    /// η [m] (unramped) at (x, y, t); fills `cs` with (cos θ_i, sin θ_i) for reuse.
    #[inline]
    pub(crate) fn elevation(&self, x: f64, y: f64, t: f64, cs: &mut [(f64, f64)]) -> f64 {
        let mut eta = 0.0;
        for i in 0..self.amp.len() {
            let th = self.kx[i] * x + self.ky[i] * y - self.omega[i] * t + self.phase[i];
            let (s, c) = crate::trig::sin_cos(th);
            cs[i] = (c, s);
            eta += self.amp[i] * c;
        }
        eta
    }

    /// η [m] (unramped) at (x, y, t) without a scratch buffer.
    pub fn elevation_only(&self, x: f64, y: f64, t: f64) -> f64 {
        let mut eta = 0.0;
        for i in 0..self.amp.len() {
            let th = self.kx[i] * x + self.ky[i] * y - self.omega[i] * t + self.phase[i];
            eta += self.amp[i] * crate::trig::sin_cos(th).1;
        }
        eta
    }

    /// Unramped kinematics at evaluation height `zs`, with (cos θ_i, sin θ_i) from
    /// [`Self::elevation`].
    #[inline]
    pub(crate) fn kinematics(&self, zs: f64, cs: &[(f64, f64)]) -> RawKinematics {
        let (mut uh_x, mut uh_y, mut w) = (0.0, 0.0, 0.0);
        let (mut ah_x, mut ah_y, mut az) = (0.0, 0.0, 0.0);
        let mut p = 0.0;
        for i in 0..self.amp.len() {
            let (c, s) = cs[i];
            let (cz, sz, kz) =
                depth_functions(self.k[i], zs, self.e[i], self.inv_m[i], self.inv_p[i]);
            let wa = self.omega[i] * self.amp[i];
            let w2a = self.omega[i] * wa;
            let uh = wa * cz * c;
            let ah = w2a * cz * s;
            uh_x += uh * self.cos_b[i];
            uh_y += uh * self.sin_b[i];
            ah_x += ah * self.cos_b[i];
            ah_y += ah * self.sin_b[i];
            w += wa * sz * s;
            az -= w2a * sz * c;
            p += self.amp[i] * kz * c;
        }
        RawKinematics {
            vel: [uh_x, uh_y, w],
            acc: [ah_x, ah_y, az],
            p_over_rho: self.g * p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn one(h: f64, z: f64) -> RawKinematics {
        let c = Component::new(1.0, 8.0, 0.0, 0.0, Depth::Finite(h), 9.81).unwrap();
        let s = LinearSum::new(vec![c], Depth::Finite(h), 9.81);
        let mut cs = [(0.0, 0.0)];
        s.elevation(0.0, 0.0, 0.0, &mut cs);
        s.kinematics(z, &cs)
    }

    #[test]
    fn spec_e3_e4_velocity_amplitude() {
        assert!((one(50.0, 0.0).vel[0] - 0.7882566617).abs() < 5e-11);
        assert!((one(50.0, -10.0).vel[0] - 0.4212894817).abs() < 5e-11);
    }

    #[test]
    fn depth_functions_match_hyperbolic_forms() {
        let (k, h) = (0.07, 30.0);
        for z in [-30.0, -20.0, -5.0, 0.0, 1.0] {
            let (e, im, ip) = depth_constants(k, Depth::Finite(h));
            let (c, s, kk) = depth_functions(k, z, e, im, ip);
            let a = k * (z + h);
            assert!((c - a.cosh() / (k * h).sinh()).abs() < 1e-13);
            assert!((s - a.sinh() / (k * h).sinh()).abs() < 1e-13);
            assert!((kk - a.cosh() / (k * h).cosh()).abs() < 1e-13);
        }
    }

    #[test]
    fn deep_water_limit_and_no_overflow() {
        let w = 2.0 * PI / 8.0;
        let kd = w * w / 9.80665;
        for z in [0.0, -5.0, -50.0] {
            let deep = c_of_z(kd, z, Depth::Infinite);
            for h in [1e3, 1e5] {
                let k = crate::dispersion::wave_number(w, Depth::Finite(h), 9.80665).unwrap();
                assert!((c_of_z(k, z, Depth::Finite(h)) - deep).abs() < 1e-12);
            }
        }
        // kh up to 1e4: finite values down to the seabed.
        let k = 1.0;
        for z in [0.0, -100.0, -1e4] {
            let (e, im, ip) = depth_constants(k, Depth::Finite(1e4));
            let (c, s, kk) = depth_functions(k, z, e, im, ip);
            assert!(c.is_finite() && s.is_finite() && kk.is_finite());
        }
    }
}
