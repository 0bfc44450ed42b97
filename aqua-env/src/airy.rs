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
    let ez = crate::trig::exp_kernel(k * z);
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
    /// ω_i a_i [m/s] and ω_i² a_i [m/s²].
    wa: Vec<f64>,
    w2a: Vec<f64>,
    cos_b: Vec<f64>,
    sin_b: Vec<f64>,
    e: Vec<f64>,
    inv_m: Vec<f64>,
    inv_p: Vec<f64>,
    depth: Depth,
    g: f64,
    /// The widest vector instructions this CPU has (detected once): the per-component loops
    /// are compiled for each and the best is taken at run time. Every variant does the same
    /// IEEE operations in the same order, so results do not depend on the CPU.
    arch: pulp::Arch,
}

/// Per-thread scratch of one point's sum: a slot per component for each term, so that the
/// per-component work runs as loops without reductions (which vectorise) and the sums as
/// plain loops in component order. Slots: cos θ_i, sin θ_i [-]; ωaC cos θ, ω²aC sin θ [m/s,
/// m/s²] (horizontal, along β_i); ωaS sin θ, ω²aS cos θ [m/s, m/s²] (vertical); aK cos θ [m].
#[derive(Debug, Default)]
pub(crate) struct SumScratch {
    cos: Vec<f64>,
    sin: Vec<f64>,
    uh: Vec<f64>,
    ah: Vec<f64>,
    w: Vec<f64>,
    az: Vec<f64>,
    p: Vec<f64>,
}

impl SumScratch {
    /// Grows every slot to n components (allocates only when n grows).
    pub(crate) fn fit(&mut self, n: usize) {
        for v in [
            &mut self.cos,
            &mut self.sin,
            &mut self.uh,
            &mut self.ah,
            &mut self.w,
            &mut self.az,
            &mut self.p,
        ] {
            if v.len() < n {
                v.resize(n, 0.0);
            }
        }
    }
}

/// (cos θ_i, sin θ_i) of θ_i = kx_i x + ky_i y − ω_i t + φ_i into `cos`, `sin` (all slices of
/// one length); its output is false if some |θ_i| is beyond the kernel's range. A
/// [`pulp::WithSimd`] whose body is inlined into each instruction set's variant.
struct Phases<'a> {
    /// (x [m], y [m], t [s]).
    at: (f64, f64, f64),
    kx: &'a [f64],
    ky: &'a [f64],
    omega: &'a [f64],
    phase: &'a [f64],
    cos: &'a mut [f64],
    sin: &'a mut [f64],
}

impl pulp::WithSimd for Phases<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> bool {
        let (x, y, t) = self.at;
        let n = self.cos.len();
        let (kx, ky, omega, phase) = (
            &self.kx[..n],
            &self.ky[..n],
            &self.omega[..n],
            &self.phase[..n],
        );
        let sin = &mut self.sin[..n];
        let mut in_range = true;
        for i in 0..n {
            let th = kx[i] * x + ky[i] * y - omega[i] * t + phase[i];
            in_range &= th.abs() <= crate::trig::KERNEL_RANGE;
            let (s, c) = crate::trig::sin_cos_kernel(th);
            self.cos[i] = c;
            sin[i] = s;
        }
        in_range
    }
}

/// Each component's velocity, acceleration and pressure terms at height `zs` into the
/// scratch: ωaC cos θ, ω²aC sin θ, ωaS sin θ, ω²aS cos θ, aK cos θ (a [`pulp::WithSimd`]).
struct Terms<'a> {
    sum: &'a LinearSum,
    /// Evaluation height z_s [m].
    zs: f64,
    sc: &'a mut SumScratch,
}

impl pulp::WithSimd for Terms<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let (s, sc, zs) = (self.sum, self.sc, self.zs);
        let n = s.amp.len();
        let (k, e, im, ip) = (&s.k[..n], &s.e[..n], &s.inv_m[..n], &s.inv_p[..n]);
        let (amp, wa, w2a) = (&s.amp[..n], &s.wa[..n], &s.w2a[..n]);
        let (cos, sin) = (&sc.cos[..n], &sc.sin[..n]);
        let (uh, ah) = (&mut sc.uh[..n], &mut sc.ah[..n]);
        let (w, az, p) = (&mut sc.w[..n], &mut sc.az[..n], &mut sc.p[..n]);
        for i in 0..n {
            let (cz, sz, kz) = depth_functions(k[i], zs, e[i], im[i], ip[i]);
            let (c, s) = (cos[i], sin[i]);
            uh[i] = wa[i] * cz * c;
            ah[i] = w2a[i] * cz * s;
            w[i] = wa[i] * sz * s;
            az[i] = w2a[i] * sz * c;
            p[i] = amp[i] * kz * c;
        }
    }
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
            wa: Vec::with_capacity(n),
            w2a: Vec::with_capacity(n),
            cos_b: Vec::with_capacity(n),
            sin_b: Vec::with_capacity(n),
            e: Vec::with_capacity(n),
            inv_m: Vec::with_capacity(n),
            inv_p: Vec::with_capacity(n),
            components,
            depth,
            g,
            arch: pulp::Arch::new(),
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
            s.wa.push(c.omega * c.amplitude);
            s.w2a.push(c.omega * (c.omega * c.amplitude));
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

    /// η [m] (unramped) at (x, y, t); fills the scratch's cos θ_i, sin θ_i for
    /// [`Self::kinematics`] (the scratch must [fit](SumScratch::fit) the component count).
    #[inline]
    pub(crate) fn elevation(&self, x: f64, y: f64, t: f64, sc: &mut SumScratch) -> f64 {
        let n = self.amp.len();
        let (cos, sin) = (&mut sc.cos[..n], &mut sc.sin[..n]);
        let (kx, ky, om, ph) = (
            &self.kx[..n],
            &self.ky[..n],
            &self.omega[..n],
            &self.phase[..n],
        );
        let in_range = self.arch.dispatch(Phases {
            at: (x, y, t),
            kx,
            ky,
            omega: om,
            phase: ph,
            cos: &mut *cos,
            sin: &mut *sin,
        });
        if !in_range {
            for i in 0..n {
                let th = kx[i] * x + ky[i] * y - om[i] * t + ph[i];
                (sin[i], cos[i]) = crate::trig::sin_cos(th);
            }
        }
        let mut eta = 0.0;
        for (a, c) in self.amp.iter().zip(cos.iter()) {
            eta += a * c;
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

    /// Unramped kinematics at evaluation height `zs`, with cos θ_i, sin θ_i from
    /// [`Self::elevation`]. The terms of each component first (a loop without reductions, so
    /// vectorised), then the sums in component order.
    #[inline]
    pub(crate) fn kinematics(&self, zs: f64, sc: &mut SumScratch) -> RawKinematics {
        let n = self.amp.len();
        self.arch.dispatch(Terms { sum: self, zs, sc });
        let (mut uh_x, mut uh_y, mut w) = (0.0, 0.0, 0.0);
        let (mut ah_x, mut ah_y, mut az) = (0.0, 0.0, 0.0);
        let mut p = 0.0;
        let (cb, sb) = (&self.cos_b[..n], &self.sin_b[..n]);
        for i in 0..n {
            let (uh, ah) = (sc.uh[i], sc.ah[i]);
            uh_x += uh * cb[i];
            uh_y += uh * sb[i];
            ah_x += ah * cb[i];
            ah_y += ah * sb[i];
            w += sc.w[i];
            az -= sc.az[i];
            p += sc.p[i];
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
        let mut sc = SumScratch::default();
        sc.fit(1);
        s.elevation(0.0, 0.0, 0.0, &mut sc);
        s.kinematics(z, &mut sc)
    }

    /// A 37-component short-crested finite-depth sum (odd: vector loops have a tail).
    fn spread_sum(depth: Depth) -> LinearSum {
        let comps = (0..37)
            .map(|i| {
                let f = i as f64;
                let period = 3.0 + 0.4 * f;
                Component::new(0.05 + 0.01 * f, period, 0.3 * f - 5.0, 1.7 * f, depth, 9.81)
                    .unwrap()
            })
            .collect();
        LinearSum::new(comps, depth, 9.81)
    }

    /// The sum written plainly: one loop, libm's exp, sin and cos.
    fn plain(s: &LinearSum, x: f64, y: f64, t: f64, z: f64) -> (f64, RawKinematics) {
        let (mut eta, mut k) = (0.0, RawKinematics::default());
        for c in s.components() {
            let (sb, cb) = c.direction.sin_cos();
            let th = c.k * (x * cb + y * sb) - c.omega * t + c.phase;
            let (cz, sz, kz) = match s.depth() {
                Depth::Infinite => {
                    let e = (c.k * z).exp();
                    (e, e, e)
                }
                Depth::Finite(h) => {
                    let (a, kh) = (c.k * (z + h), c.k * h);
                    (
                        a.cosh() / kh.sinh(),
                        a.sinh() / kh.sinh(),
                        a.cosh() / kh.cosh(),
                    )
                }
            };
            let (wa, w2a) = (c.omega * c.amplitude, c.omega * c.omega * c.amplitude);
            eta += c.amplitude * th.cos();
            k.vel[0] += wa * cz * th.cos() * cb;
            k.vel[1] += wa * cz * th.cos() * sb;
            k.vel[2] += wa * sz * th.sin();
            k.acc[0] += w2a * cz * th.sin() * cb;
            k.acc[1] += w2a * cz * th.sin() * sb;
            k.acc[2] -= w2a * sz * th.cos();
            k.p_over_rho += 9.81 * c.amplitude * kz * th.cos();
        }
        (eta, k)
    }

    #[test]
    fn vector_and_scalar_instruction_sets_agree_bit_for_bit_and_with_the_plain_sum() {
        for depth in [Depth::Finite(40.0), Depth::Infinite] {
            let fast = spread_sum(depth);
            if matches!(fast.arch, pulp::Arch::Scalar) {
                eprintln!("this CPU has no vector variant: scalar compared with scalar only");
            }
            let mut scalar = fast.clone();
            scalar.arch = pulp::Arch::Scalar;
            let (mut a, mut b) = (SumScratch::default(), SumScratch::default());
            a.fit(fast.len());
            b.fit(fast.len());
            for j in 0..200 {
                let f = j as f64;
                let (x, y, t, z) = (7.3 * f - 400.0, 3.1 * f, 0.37 * f, -0.19 * f);
                let ea = fast.elevation(x, y, t, &mut a);
                let eb = scalar.elevation(x, y, t, &mut b);
                let (ka, kb) = (fast.kinematics(z, &mut a), scalar.kinematics(z, &mut b));
                assert_eq!(ea.to_bits(), eb.to_bits());
                assert_eq!(ka, kb, "{depth:?} at {x} {y} {t} {z}");
                let (ep, kp) = plain(&fast, x, y, t, z);
                let close = |u: f64, v: f64, scale: f64| (u - v).abs() <= 1e-13 * scale;
                assert!(close(ea, ep, 1.0), "{ea} vs {ep}");
                for c in 0..3 {
                    assert!(close(ka.vel[c], kp.vel[c], 1.0), "{ka:?} vs {kp:?}");
                    assert!(close(ka.acc[c], kp.acc[c], 1.0), "{ka:?} vs {kp:?}");
                }
                assert!(close(ka.p_over_rho, kp.p_over_rho, 10.0));
            }
            // Phases beyond the kernel's range (t = 1e7 s) take the library's sin/cos for every
            // component: the same bits as the plain per-component sum.
            for t in [1e7, -3e7] {
                let e = fast.elevation(12.0, -3.0, t, &mut a);
                assert_eq!(e.to_bits(), fast.elevation_only(12.0, -3.0, t).to_bits());
            }
        }
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
