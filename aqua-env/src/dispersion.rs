//! The linear dispersion relation ω² = g·k·tanh(k·h), solved exactly
//! (docs/theory/environment.md#dispersion-relation).

use crate::constants::Depth;
use crate::error::EnvError;

/// Wave number k [rad/m] for angular frequency ω [rad/s], depth and gravity g [m/s²].
///
/// Newton's method from Eckart's approximation; stops at |Δk| ≤ 1e-12·k (at most 50 iterations).
/// Infinite depth gives k = ω²/g exactly. There is no shallow/deep switch: for large kh,
/// tanh(kh) → 1 and the iteration reproduces the deep-water value.
pub fn wave_number(omega: f64, depth: Depth, g: f64) -> Result<f64, EnvError> {
    let k_deep = omega * omega / g;
    let h = match depth {
        Depth::Infinite => return Ok(k_deep),
        Depth::Finite(h) => h,
    };
    let fail = EnvError::Dispersion { omega, depth: h };
    if !(omega > 0.0 && h > 0.0 && g > 0.0) || !omega.is_finite() || !h.is_finite() {
        return Err(fail);
    }
    let mut k = k_deep / (k_deep * h).tanh().sqrt();
    for _ in 0..50 {
        let th = (k * h).tanh();
        let f = g * k * th - omega * omega;
        let df = g * th + g * k * h * (1.0 - th * th);
        let dk = f / df;
        k -= dk;
        if !k.is_finite() || k <= 0.0 {
            return Err(fail);
        }
        if dk.abs() <= 1e-12 * k {
            return Ok(k);
        }
    }
    Err(fail)
}

/// Group velocity c_g = (c/2)·(1 + 2kh/sinh 2kh) [m/s] (c for infinite depth → c/2).
pub fn group_velocity(omega: f64, k: f64, depth: Depth) -> f64 {
    let c = omega / k;
    match depth {
        Depth::Infinite => 0.5 * c,
        Depth::Finite(h) => {
            let x = 2.0 * k * h;
            // 2kh/sinh(2kh) written overflow-free: 2x·e^{−x}/(1 − e^{−2x}).
            let ratio = if x > 700.0 {
                0.0
            } else {
                2.0 * x * (-x).exp() / (-(-2.0 * x).exp_m1())
            };
            0.5 * c * (1.0 + ratio)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn spec_e1_e2() {
        let w = 2.0 * PI / 8.0;
        let k = wave_number(w, Depth::Finite(50.0), 9.80665).unwrap();
        assert!((k - 0.0631296721374).abs() < 5e-14, "{k}");
        assert!((2.0 * PI / k - 99.5282423375).abs() < 5e-11);
        let k = wave_number(w, Depth::Finite(50.0), 9.81).unwrap();
        assert!((k - 0.0631085967798).abs() < 5e-14, "{k}");
        assert!((2.0 * PI / k - 99.5614801752).abs() < 5e-11);
    }

    #[test]
    fn deep_water_continuity() {
        let w = 2.0 * PI / 8.0;
        let kd = wave_number(w, Depth::Infinite, 9.80665).unwrap();
        for h in [1e3, 1e5] {
            let k = wave_number(w, Depth::Finite(h), 9.80665).unwrap();
            assert!(((k - kd) / kd).abs() < 1e-12);
        }
    }

    #[test]
    fn residual_small_over_range() {
        for &t in &[1.0, 3.0, 8.0, 15.0, 30.0] {
            for &h in &[0.05, 1.0, 10.0, 100.0, 1e5] {
                let w = 2.0 * PI / t;
                let k = wave_number(w, Depth::Finite(h), 9.81).unwrap();
                let r = 9.81 * k * (k * h).tanh() - w * w;
                assert!(r.abs() < 1e-11 * w * w, "T={t} h={h}");
            }
        }
    }

    #[test]
    fn group_velocity_limits() {
        let w = 2.0 * PI / 8.0;
        let k = wave_number(w, Depth::Finite(1e5), 9.81).unwrap();
        assert!((group_velocity(w, k, Depth::Finite(1e5)) - 0.5 * w / k).abs() < 1e-12);
        // shallow water: c_g → c
        let k = wave_number(w, Depth::Finite(0.1), 9.81).unwrap();
        let cg = group_velocity(w, k, Depth::Finite(0.1));
        let x = 2.0 * k * 0.1;
        let direct = 0.5 * (w / k) * (1.0 + x / x.sinh());
        assert!((cg - direct).abs() < 1e-12 * direct);
        assert!((cg / (w / k) - 1.0).abs() < 3e-3);
    }
}
