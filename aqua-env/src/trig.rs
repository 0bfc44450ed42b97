//! A branch-free sin/cos and exp for the wave sums: Cody–Waite reduction by π/2 and the minimax
//! kernels of fdlibm (Sun Microsystems, freely distributable), written out here.
//!
//! Why not `f64::sin_cos`: the wave sums call it for every component at every point and it
//! dominated the sea evaluation (a libm call per component, no vectorisation). This version
//! inlines, has no calls, and is pure f64 arithmetic in a fixed order, so its results are the
//! same on every platform (libm's may differ between versions). Accuracy: within 2 ulp of the
//! exact value for |x| ≤ 1e6 rad (tested against `f64::sin_cos`); larger arguments fall back
//! to `f64::sin_cos`.

const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// First 33 bits of π/2 (n·PIO2_HI is exact for |n| < 2^20).
const PIO2_HI: f64 = 1.570_796_326_734_125_6;
/// π/2 − PIO2_HI.
const PIO2_LO: f64 = 6.077_100_506_506_192e-11;

const S1: f64 = -1.666_666_666_666_663_2e-1;
const S2: f64 = 8.333_333_333_322_49e-3;
const S3: f64 = -1.984_126_982_985_795e-4;
const S4: f64 = 2.755_731_370_707_006_8e-6;
const S5: f64 = -2.505_076_025_340_686_3e-8;
const S6: f64 = 1.589_690_995_211_55e-10;

#[allow(clippy::excessive_precision)]
const C1: f64 = 4.166_666_666_666_660_2e-2;
const C2: f64 = -1.388_888_888_887_411e-3;
const C3: f64 = 2.480_158_728_947_673e-5;
const C4: f64 = -2.755_731_435_139_066_3e-7;
const C5: f64 = 2.087_572_321_298_175e-9;
const C6: f64 = -1.135_964_755_778_819_5e-11;

/// (sin x, cos x).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !(x.abs() <= KERNEL_RANGE) {
        return x.sin_cos();
    }
    sin_cos_kernel(x)
}

/// |x| [rad] up to which [`sin_cos_kernel`] holds its accuracy.
pub const KERNEL_RANGE: f64 = 1e6;

/// (sin x, cos x) for |x| ≤ [`KERNEL_RANGE`], with no branch and no call, so that a loop of
/// it vectorises; outside that range the result is meaningless (callers check the range).
#[inline(always)]
pub fn sin_cos_kernel(x: f64) -> (f64, f64) {
    // Round to nearest by the 1.5·2^52 trick: pure arithmetic (f64::round is a libm call on
    // the baseline x86-64 target). The sum's low mantissa bits are n itself (2^51 + n), so the
    // quadrant is read from its bits: no float-to-integer conversion, which x86 cannot do on
    // vectors of f64 before AVX-512.
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    let shifted = x * INV_PIO2 + SHIFT;
    let n = shifted - SHIFT;
    let r = (x - n * PIO2_HI) - n * PIO2_LO;
    let z = r * r;
    let s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let c = 1.0 - 0.5 * z + z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    // The quadrant q picks (s, c), (c, −s), (−s, −c) or (−c, s). Selected without a branch:
    // q is random across the components of a wave sum, and a mispredicted jump per component
    // cost more than the kernels (bench `sea_eval`).
    let q = shifted.to_bits();
    let odd = q & 1 == 1;
    let (a, b) = (if odd { c } else { s }, if odd { s } else { c });
    let sin_sign = (q & 2) << 62;
    let cos_sign = (q.wrapping_add(1) & 2) << 62;
    (
        f64::from_bits(a.to_bits() ^ sin_sign),
        f64::from_bits(b.to_bits() ^ cos_sign),
    )
}

/// e^x without a branch or a call (so that a loop of it vectorises): the reduction
/// x = k·ln 2 + r, |r| ≤ ½ ln 2, and the rational kernel of fdlibm's `exp` (Remez, error below
/// 2^−59 on that interval), then the scaling by 2^k as 2^a·2^b with a + b = k, |a|, |b| ≤ 512,
/// each built from its exponent bits (2^1024 itself is not a double). Within 1 ulp of the
/// exact value for −708 ≤ x ≤ ln(f64::MAX) ≈ 709.78 (tested against `f64::exp`); 0 below −708
/// (where e^x < 3.3e−308), +∞ above ln(f64::MAX), NaN for NaN.
#[inline(always)]
pub fn exp_kernel(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    const INV_LN2: f64 = std::f64::consts::LOG2_E;
    const P1: f64 = 1.666_666_666_666_660_2e-1;
    const P2: f64 = -2.777_777_777_701_559_3e-3;
    const P3: f64 = 6.613_756_321_437_934e-5;
    const P4: f64 = -1.653_390_220_546_525_2e-6;
    const P5: f64 = 4.138_136_797_057_238_5e-8;
    /// ln(f64::MAX).
    const X_MAX: f64 = 709.782_712_893_384;
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    // Clamped so that k stays in [−1021, 1024]; the ends are selected below.
    let xc = x.clamp(-708.0, X_MAX);
    let shifted = xc * INV_LN2 + SHIFT;
    let k = shifted - SHIFT;
    let hi = xc - k * LN2_HI;
    let lo = k * LN2_LO;
    let r = hi - lo;
    let t = r * r;
    let c = r - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
    let y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi);
    // An integer m sits as m + 2^51 in the low mantissa bits of m + SHIFT, so its bits minus
    // SHIFT's are m; 2^m has exponent field m + 1023. Both factors and both products are
    // normal numbers, so the scaling is exact.
    let half = k * 0.5 + SHIFT;
    let a = half - SHIFT;
    let pow2 = |m_plus_shift: f64| {
        let m = m_plus_shift.to_bits().wrapping_sub(SHIFT.to_bits());
        f64::from_bits(m.wrapping_add(1023) << 52)
    };
    let e = (y * pow2(half)) * pow2((k - a) + SHIFT);
    if x < -708.0 {
        0.0
    } else if x > X_MAX {
        f64::INFINITY
    } else if x.is_nan() {
        x
    } else {
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn quadrants_and_special_points() {
        for k in -8..=8 {
            let x = k as f64 * std::f64::consts::FRAC_PI_4;
            let (s, c) = sin_cos(x);
            let (se, ce) = x.sin_cos();
            assert!((s - se).abs() < 4e-16 && (c - ce).abs() < 4e-16, "x = {x}");
        }
        let (s, c) = sin_cos(1e7);
        assert_eq!((s, c), 1e7f64.sin_cos());
    }

    /// Distance in units in the last place.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn exp_ends_and_special_points() {
        assert_eq!(exp_kernel(0.0), 1.0);
        assert!(ulps(exp_kernel(1.0), std::f64::consts::E) <= 1);
        assert!(ulps(exp_kernel(-708.0), (-708.0f64).exp()) <= 1);
        assert!(ulps(exp_kernel(709.0), 709.0f64.exp()) <= 1);
        for x in [709.5, 709.78, 709.782_712_893_384] {
            assert!(ulps(exp_kernel(x), x.exp()) <= 1, "x = {x}");
        }
        assert_eq!(exp_kernel(-708.5), 0.0);
        assert_eq!(exp_kernel(-1e300), 0.0);
        assert_eq!(exp_kernel(710.0), f64::INFINITY);
        assert!(exp_kernel(f64::NAN).is_nan());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn matches_libm(x in -1e6f64..1e6) {
            let (s, c) = sin_cos(x);
            let (se, ce) = x.sin_cos();
            // the reduction error grows like |n|·ulp(π/2 tail) ≪ 1e-16 here
            prop_assert!((s - se).abs() <= 5e-16 && (c - ce).abs() <= 5e-16, "x = {}: {} {} vs {} {}", x, s, c, se, ce);
        }

        #[test]
        fn exp_within_one_ulp_of_libm(x in -708.0f64..709.782) {
            prop_assert!(ulps(exp_kernel(x), x.exp()) <= 1, "x = {}: {} vs {}", x, exp_kernel(x), x.exp());
        }

        #[test]
        fn exp_within_one_ulp_near_zero(x in -1.0f64..1.0) {
            prop_assert!(ulps(exp_kernel(x), x.exp()) <= 1, "x = {}", x);
        }
    }
}
