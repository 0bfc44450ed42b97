//! The step-to-step ripple of the peak tension: the alternating, high-frequency content that an
//! undamped scheme keeps on the largest tension near its top, which the time step does not
//! resolve and the time-step indicator (a coarsely sampled crest) does not see
//! (docs/theory/fem.md#step-ripple-indicator).

use super::StepControl;
use serde::{Deserialize, Serialize};

/// Windows of four steps touching the top quarter of the range that the ripple needs before it
/// is estimated: fewer are a crest's shape, not a ripple.
pub const MIN_RIPPLE_WINDOWS: usize = 8;

/// The ripple of the peak tension series T_pk(t_n) near its top
/// (docs/theory/fem.md#step-ripple-indicator).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct StepRipple {
    /// Root mean square of the alternating part a_n = |ΔT³_n|/8 over the windows of four steps
    /// touching the top quarter of the range, relative to the largest peak tension: for a
    /// step-to-step alternation ±a on a smooth history it is a/T_max.
    pub ripple: f64,
    /// The largest of those a_n, relative to the largest peak tension.
    pub largest: f64,
    /// Windows of four steps counted (0 when fewer than [`MIN_RIPPLE_WINDOWS`]: no estimate).
    pub windows: usize,
    /// The element carrying the peak at the step of the largest a_n, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub element: Option<usize>,
}

impl StepControl {
    /// The step-to-step ripple of the peak tension near its top; see [`StepRipple`].
    pub fn step_ripple(&self) -> StepRipple {
        step_ripple(&self.peak_tensions, &self.peak_elements)
    }
}

/// The ripple of a peak-tension series `t` (one value per accepted step) whose peaks were
/// carried by `elements` (may be shorter: then unknown). The third difference
/// ΔT³_n = −T_{n−1} + 3T_n − 3T_{n+1} + T_{n+2} is 8·a for an alternation ±a and only
/// A·(2 sin(φ/2))³ ≈ A·φ³ for a sine of half range A sampled at the phase step φ, so a smooth
/// history resolved by the step (φ ≲ 0.3 where the time-step indicator is quiet) adds little.
pub fn step_ripple(t: &[f64], elements: &[usize]) -> StepRipple {
    let (lo, hi) = t
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    if t.len() < 4 || hi <= lo || hi <= 0.0 {
        return StepRipple::default();
    }
    // The top quarter of the range, as for the time-step indicator.
    let top = hi - 0.25 * (hi - lo);
    let (mut sum, mut largest, mut windows, mut at) = (0.0, 0.0f64, 0usize, None);
    for (i, w) in t.windows(4).enumerate() {
        if w[1] < top && w[2] < top {
            continue;
        }
        let a = (-w[0] + 3.0 * w[1] - 3.0 * w[2] + w[3]).abs() / 8.0;
        sum += a * a;
        windows += 1;
        if a > largest {
            largest = a;
            at = Some(if w[1] >= w[2] { i + 1 } else { i + 2 });
        }
    }
    if windows < MIN_RIPPLE_WINDOWS {
        return StepRipple::default();
    }
    StepRipple {
        ripple: (sum / windows as f64).sqrt() / hi,
        largest: largest / hi,
        windows,
        element: at.and_then(|i| elements.get(i).copied()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth sine sampled coarsely (20 steps a period, the time-step indicator ε_T 0.35 %) has almost no ripple; the same with a step-to-step alternation of
    /// ±2 % of its peak reads that 2 %.
    #[test]
    fn a_sampled_sine_has_no_ripple_and_an_alternation_is_read() {
        let (m, a) = (1000.0, 400.0);
        let phi = 2.0 * std::f64::consts::PI / 20.0;
        let sine: Vec<f64> = (0..400)
            .map(|n| m + a * (phi * n as f64 + 0.3).sin())
            .collect();
        let r = step_ripple(&sine, &[]);
        assert!(r.windows >= MIN_RIPPLE_WINDOWS, "{r:?}");
        assert!(r.ripple < 0.002, "smooth sine: {r:?}");
        let alt = 0.02 * (m + a);
        let rippled: Vec<f64> = sine
            .iter()
            .enumerate()
            .map(|(n, x)| x + if n % 2 == 0 { alt } else { -alt })
            .collect();
        let r = step_ripple(&rippled, &[]);
        let want = alt / (m + a + alt);
        assert!(
            (r.ripple - want).abs() < 0.15 * want,
            "rippled sine: {r:?}, want {want:.4}"
        );
        assert!(r.largest >= r.ripple);
    }

    /// A crest of a few steps (a coarse step on a short rise) gives no estimate, and the
    /// element of the largest ripple is named.
    #[test]
    fn few_windows_give_no_estimate_and_the_element_is_named() {
        let r = step_ripple(&[0.0, 0.5, 1.0, 0.7, 0.2], &[1, 1, 1, 1, 1]);
        assert_eq!(r, StepRipple::default());
        let mut t: Vec<f64> = (0..100).map(|n| 10.0 + (0.05 * n as f64).sin()).collect();
        let mut elements = vec![3; t.len()];
        for n in 30..34 {
            t[n] += if n % 2 == 0 { 0.3 } else { -0.3 };
        }
        elements[30] = 7;
        elements[32] = 7;
        let r = step_ripple(&t, &elements);
        assert_eq!(r.element, Some(7), "{r:?}");
    }
}
