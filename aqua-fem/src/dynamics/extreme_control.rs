//! Extremes to a tolerance (docs/theory/fem.md#extremes-to-a-tolerance): with
//! `extreme_tolerance` set, a converged step is also rejected (and the step halved) when a
//! crest of a group's peak tension lies inside it and its samples miss that crest by more than
//! the tolerance of the group's largest tension.
//!
//! For each element group g, T_g(t) = max over its elements of the axial force, and Ṫ_g its
//! rate, the elastic rate of that element: Ṫ = (EA/L0)·ê·(v_b − v_a) while taut, 0 slack. At
//! both ends of a step of length h the pair (T, Ṫ) is known, so the cubic Hermite interpolant
//! p(s) on [0, h] follows the tension inside the step to O(h⁴). Where Ṫ goes from ≥ 0 to < 0,
//! a crest lies inside; its height is the largest p(s*) at a zero of p′, and the step is
//! accepted when
//!
//! p(s*) − max(T_n, T_{n+1}) ≤ tol · max(T_g,max, p(s*)),
//!
//! checked only where the crest could set the group's extreme (p(s*) ≥ (1 − tol)·T_g,max). A
//! snap that starts slack (T = Ṫ = 0) and passes its crest within the step is caught the same
//! way; one that starts and ends slack within a single step leaves no trace at the step's ends
//! and is not (the snap check of `snap_resolution.rs` sees it at the step's middle and warns). Groups whose largest tension is below `MIN_SHARE` of the structure's largest
//! are not controlled. A step that cannot be halved again without falling below `dt_min` is
//! accepted and counted as unresolved, so the run goes on and says so.

use super::DynamicSolver;
use crate::failure::FailureReason;
use crate::model::Model;
use crate::system::sub;
use serde::{Deserialize, Serialize};

/// Groups whose largest tension is below this share of the structure's largest are not
/// controlled: their extremes are not design values and their crests are round-off of the
/// structure's peak [-].
const MIN_SHARE: f64 = 0.05;

/// What the extreme control did over the run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ExtremeResolution {
    /// The tolerance asked for (relative error of each group's largest tension).
    pub tolerance: f64,
    /// Converged steps rejected because a crest was sampled too coarsely.
    pub rejections: usize,
    /// Steps accepted at the floor `dt_min` with a crest still coarser than the tolerance.
    pub unresolved_steps: usize,
    /// The largest estimated crest error among those unresolved steps (relative).
    pub worst_unresolved: f64,
    /// The group of that step, if any.
    pub worst_group: Option<usize>,
}

/// Per-group peak tension and its rate at the last accepted step, and the control's state.
#[derive(Debug, Clone)]
pub(crate) struct ExtremeControl {
    tolerance: f64,
    /// T_g [N] and Ṫ_g [N/s] at the last accepted state.
    now: Vec<(f64, f64)>,
    /// Largest T_g over the accepted states [N].
    hi: Vec<f64>,
    /// (T_g, Ṫ_g) of the trial state (scratch).
    trial: Vec<(f64, f64)>,
}

impl ExtremeControl {
    pub(crate) fn new(model: &Model, tolerance: f64) -> Self {
        let n = model.groups().len();
        Self {
            tolerance,
            now: vec![(0.0, 0.0); n],
            hi: vec![f64::NEG_INFINITY; n],
            trial: vec![(0.0, 0.0); n],
        }
    }

    /// Per group, the largest element tension and the elastic rate of that element, into `out`.
    fn group_peaks(
        model: &Model,
        tension: &[f64],
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        out: &mut [(f64, f64)],
    ) {
        let elements = model.elements();
        for (o, g) in out.iter_mut().zip(model.groups()) {
            let Some(&e) = g
                .elements
                .iter()
                .max_by(|&&a, &&b| tension[a].total_cmp(&tension[b]))
            else {
                *o = (0.0, 0.0);
                continue;
            };
            let el = &elements[e];
            let d = sub(x[el.b], x[el.a]);
            let dv = sub(v[el.b], v[el.a]);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let rate = if l > el.l0 && l > 0.0 {
                el.ea / el.l0 * (d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2]) / l
            } else {
                0.0
            };
            *o = (tension[e], rate);
        }
    }

    /// Records an accepted state's tensions, positions and velocities.
    pub(crate) fn accept(
        &mut self,
        model: &Model,
        tension: &[f64],
        x: &[[f64; 3]],
        v: &[[f64; 3]],
    ) {
        let mut now = std::mem::take(&mut self.now);
        Self::group_peaks(model, tension, x, v, &mut now);
        for (n, hi) in now.iter().zip(&mut self.hi) {
            *hi = hi.max(n.0);
        }
        self.now = now;
    }

    /// The largest relative crest error of a trial step of `h` [s] over the controlled groups
    /// whose crest could set their extreme, with its group.
    fn worst(
        &mut self,
        model: &Model,
        h: f64,
        tension: &[f64],
        x: &[[f64; 3]],
        v: &[[f64; 3]],
    ) -> (f64, usize) {
        let mut trial = std::mem::take(&mut self.trial);
        Self::group_peaks(model, tension, x, v, &mut trial);
        let peak = self
            .hi
            .iter()
            .chain(trial.iter().map(|t| &t.0))
            .fold(0.0f64, |m, &t| m.max(t));
        let mut worst = (0.0, 0);
        for (g, (&(t1, r1), &(t0, r0))) in trial.iter().zip(&self.now).enumerate() {
            let hi = self.hi[g].max(t1);
            if !(hi > MIN_SHARE * peak) || !(r0 >= 0.0 && r1 < 0.0) {
                continue;
            }
            let crest = hermite_crest(t0, r0, t1, r1, h);
            if crest < (1.0 - self.tolerance) * hi {
                continue;
            }
            let e = (crest - t0.max(t1)) / hi.max(crest);
            if e > worst.0 {
                worst = (e, g);
            }
        }
        self.trial = trial;
        worst
    }
}

/// The largest value inside (0, h) of the cubic Hermite interpolant of (p(0), p′(0)) =
/// (t0, r0) and (p(h), p′(h)) = (t1, r1), or max(t0, t1) when it has no interior maximum.
fn hermite_crest(t0: f64, r0: f64, t1: f64, r1: f64, h: f64) -> f64 {
    let d = (t1 - t0) / h;
    // p(s) = t0 + r0·s + c2·s² + c3·s³.
    let c2 = (3.0 * d - 2.0 * r0 - r1) / h;
    let c3 = (r0 + r1 - 2.0 * d) / (h * h);
    let p = |s: f64| t0 + s * (r0 + s * (c2 + s * c3));
    let mut best = t0.max(t1);
    // p′(s) = r0 + 2·c2·s + 3·c3·s² = 0.
    let (a, b, c) = (3.0 * c3, 2.0 * c2, r0);
    let mut roots = [f64::NAN; 2];
    if a.abs() <= 1e-12 * (b.abs() + c.abs() / h) / h {
        if b != 0.0 {
            roots[0] = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            roots = [q / a, if q != 0.0 { c / q } else { f64::NAN }];
        }
    }
    for s in roots {
        if s > 0.0 && s < h {
            best = best.max(p(s));
        }
    }
    best
}

impl DynamicSolver<'_> {
    /// The extreme control's verdict on a converged trial step of `h` whose outputs are in
    /// `self.trial` (formed by the energy guard): a reason to halve, or `None` to accept
    /// (also when the halved step would fall below `dt_min`; it is then counted unresolved).
    pub(super) fn extreme_guard(&mut self, h: f64, dt_min: f64) -> Option<FailureReason> {
        let model = self.model;
        let ctl = self.extremes.as_mut()?;
        let tolerance = ctl.tolerance;
        let (error, group) = ctl.worst(model, h, &self.trial.tension, &self.x1, &self.v1);
        if error <= tolerance {
            return None;
        }
        let r = self
            .control
            .extremes
            .get_or_insert_with(|| ExtremeResolution {
                tolerance,
                ..Default::default()
            });
        if 0.5 * h < dt_min {
            r.unresolved_steps += 1;
            if error > r.worst_unresolved {
                r.worst_unresolved = error;
                r.worst_group = Some(group);
            }
            return None;
        }
        r.rejections += 1;
        Some(FailureReason::ExtremeUnresolved {
            group,
            error,
            tolerance,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::hermite_crest;

    #[test]
    fn hermite_crest_of_a_cubic_is_exact_and_of_a_sine_close() {
        // p(s) = 1 + s − s³ on [0, 1]: crest at s = 1/√3, p = 1 + 2/(3√3).
        let (t1, r1) = (1.0, -2.0);
        let c = hermite_crest(1.0, 1.0, t1, r1, 1.0);
        assert!((c - (1.0 + 2.0 / (3.0 * 3f64.sqrt()))).abs() < 1e-14, "{c}");
        // sin over [1, 2]: crest 1 at π/2.
        let c = hermite_crest(1f64.sin(), 1f64.cos(), 2f64.sin(), 2f64.cos(), 1.0);
        assert!((c - 1.0).abs() < 3e-3, "{c}");
        // No interior maximum: the larger end.
        assert_eq!(hermite_crest(0.0, 1.0, 1.0, 1.0, 1.0), 1.0);
    }
}
