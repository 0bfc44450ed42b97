//! Drag coefficient of an isolated smooth circular cylinder, C_cyl(Re), valid for all Re > 0
//! (docs/theory/hydrodynamics.md#cylinder-drag).
//!
//! Inside [Re_a, Re_b] the Kristiansen–Faltinsen polynomial P(log₁₀ Re) is used; outside, the
//! smooth-cylinder fit of N.-S. Cheng (2013, J. Hydraul. Eng. 139(6))
//! C_fit = 11·Re^(−0.75) + 0.9·(1 − e^(−1000/Re)) + 1.2·(1 − e^(−(Re/4500)^0.7)).
//! Re_a and Re_b are the two points where P and C_fit cross, so C_cyl is continuous.

use std::f64::consts::LN_10;

/// Lower crossing Re_a (x = log₁₀ Re = 1.3883121680).
pub const RE_A: f64 = 24.451875060;
/// Upper crossing Re_b (x = 4.3064228265).
pub const RE_B: f64 = 20249.897370;
/// Above this Reynolds number the drag crisis (not modelled) may occur: warn once.
pub const RE_CRISIS: f64 = 2e5;

/// Polynomial coefficients of P(x), lowest order first.
const P: [f64; 8] = [
    -78.46675, 254.73873, -327.88640, 223.64577, -87.922340, 20.007690, -2.4489400, 0.1247900,
];

/// P(x) and P′(x) by Horner's rule.
fn poly(x: f64) -> (f64, f64) {
    let mut p = P[7];
    let mut dp = 0.0;
    for k in (0..7).rev() {
        dp = dp * x + p;
        p = p * x + P[k];
    }
    (p, dp)
}

/// Cheng's smooth-cylinder fit and its derivative with respect to Re.
fn fit(re: f64) -> (f64, f64) {
    let a = 11.0 * re.powf(-0.75);
    let e1 = (-1000.0 / re).exp();
    let q = (re / 4500.0).powf(0.7);
    let e2 = (-q).exp();
    let c = a + 0.9 * (1.0 - e1) + 1.2 * (1.0 - e2);
    let dc = -8.25 * re.powf(-1.75) - 900.0 * e1 / (re * re)
        + (0.84 / 4500.0) * (re / 4500.0).powf(-0.3) * e2;
    (c, dc)
}

/// C_cyl(Re) and dC_cyl/dRe for Re > 0 (Re ≤ 0 is treated as a tiny positive number).
pub fn drag(re: f64) -> (f64, f64) {
    let re = re.max(f64::MIN_POSITIVE);
    if (RE_A..=RE_B).contains(&re) {
        let x = re.log10();
        let (p, dp) = poly(x);
        (p, dp / (re * LN_10))
    } else {
        fit(re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn spec_reference_values() {
        assert!((drag(10.0).0 - 2.8726619804).abs() < 5e-11);
        assert!((drag(1000.0).0 - 1.0052300000).abs() < 5e-11);
        assert!((drag(1e5).0 - 1.2107239318).abs() < 5e-11);
    }

    #[test]
    fn continuous_at_crossings() {
        for re in [RE_A, RE_B] {
            let below = drag(re * (1.0 - 1e-13)).0;
            let above = drag(re * (1.0 + 1e-13)).0;
            assert!(
                (below - above).abs() < 1e-9,
                "jump at {re}: {below} vs {above}"
            );
        }
    }

    #[test]
    fn derivative_matches_finite_differences() {
        for re in [0.3, 5.0, 20.0, 30.0, 100.0, 1260.5, 1e4, 3e4, 1e6] {
            let h = 1e-4 * re;
            let fd = (drag(re + h).0 - drag(re - h).0) / (2.0 * h);
            let d = drag(re).1;
            assert!(
                (fd - d).abs() <= 1e-6 * d.abs().max(1e-3 / re),
                "Re {re}: {d} vs fd {fd}"
            );
        }
    }

    proptest! {
        #[test]
        fn positive_and_bounded(lre in -3.0f64..8.0) {
            let c = drag(10f64.powf(lre)).0;
            prop_assert!(c > 0.3 && c.is_finite());
            // above Re = 100 the drag of a smooth cylinder stays between 0.3 and 2
            if lre > 2.0 { prop_assert!(c < 2.0); }
        }
    }
}
