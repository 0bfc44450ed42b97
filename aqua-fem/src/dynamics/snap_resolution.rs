//! Whether the time step resolves the snaps of slack cable elements
//! (docs/theory/fem.md#snap-resolution): an element that goes from slack to taut within one
//! step — or is slack at both of the step's ends but taut at its middle — snapped inside the
//! step. Its two nodes meet the element's stiffness k = EA/L0 at the closing speed v_c, which
//! they turn round in half an oscillation of their reduced mass m_r on k, π/ω with
//! ω = √(k/m_r), at a peak tension of about T* = v_c·√(k·m_r). A step longer than
//! `RESOLVED_PHASE`/ω misses that crest by more than 1 %; when such a snap's T* exceeds the
//! largest tension the run computed, the run's largest tension is not resolved by the step.
//!
//! When the run's largest tension is reached in an element in a step in which that element
//! snapped unresolved, or in the step after, that extreme is the unresolved snap's: too high or
//! too low by what the step misses of the crest (`SnapResolution::peak`). The same holds, for
//! its own extreme, of each element with one end held (an anchor's, or a prescribed
//! fairlead's), which carries the support's reaction whatever the run's largest tension is
//! (`SnapResolution::support`).
//!
//! Each element group's unresolved snaps are counted with their largest crest T*; those of the
//! group that carries the run's largest tension (`SnapResolution::peak_group`) say how much a
//! scheme that keeps the energy of unresolved modes (the midpoint rule with θ = ½) leaves
//! ringing on that extreme (docs/theory/fem.md#snap-ringing).

use crate::model::Model;
use crate::system::sub;
use serde::{Deserialize, Serialize};

/// The phase ω·Δt of the snap oscillation per step up to which a step samples its crest within
/// 1 % (a crest sampled at phase steps φ is low by at most 1 − cos(φ/2) ≈ φ²/8; φ = √0.08).
pub const RESOLVED_PHASE: f64 = 0.282_842_712_474_619;

/// Estimated snap tension above the run's largest computed tension, as a share of the latter,
/// from which a run warns that its largest tension is not resolved (1 %).
pub const SNAP_EXCESS_WARNING: f64 = 0.01;

/// The largest unresolved snap of a run (reported in run.json under `step_control.snaps`;
/// docs/theory/fem.md#snap-resolution).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SnapResolution {
    /// Unresolved snaps: elements that went taut within single steps longer than
    /// `RESOLVED_PHASE`/ω.
    pub snaps: usize,
    /// The group of the snap with the largest estimated tension.
    pub group: usize,
    /// Its element.
    pub element: usize,
    /// The time the step started from [s].
    pub t: f64,
    /// Its step Δt [s].
    pub dt: f64,
    /// The closing speed v_c of the element's ends [m/s].
    pub speed: f64,
    /// The estimated snap tension T* = v_c·√(k·m_r) [N].
    pub estimate: f64,
    /// The largest element tension over the accepted steps [N].
    pub computed: f64,
    /// (T* − computed)/computed: how far above the computed extreme the snap reaches.
    pub excess: f64,
    /// The largest step that samples this snap's crest within 1 %, `RESOLVED_PHASE`/ω [s].
    pub resolving_dt: f64,
    /// The run's largest tension if it was reached at an unresolved snap of its element (in
    /// the snap's step or the next), with a crest T* of at least 1 % of it.
    #[serde(default)]
    pub peak: Option<SnapExtreme>,
    /// The elements with one end held whose largest tension was reached at an unresolved
    /// snap of theirs (in its step or the next), largest tension first.
    #[serde(default)]
    pub support: Vec<SnapExtreme>,
    /// The unresolved snaps of the group whose element carries the run's largest tension (None
    /// when that group had none): with a scheme that keeps the energy of unresolved modes, each
    /// leaves its elements ringing at up to its crest, on top of that group's tension.
    #[serde(default)]
    pub peak_group: Option<GroupSnaps>,
}

/// The unresolved snaps of one element group.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupSnaps {
    /// The group.
    pub group: usize,
    /// How many of its elements' snaps were unresolved.
    pub snaps: usize,
    /// The largest of their estimated crests T* [N].
    pub estimate: f64,
}

/// An element whose largest tension over the run (the run's largest, or a supported
/// element's own) was reached at an unresolved snap of its own, in the snap's step or the
/// next: that extreme is not resolved by the step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct SnapExtreme {
    /// The element.
    pub element: usize,
    /// Its group.
    pub group: usize,
    /// Its largest tension [N].
    pub tension: f64,
    /// The time at which it was reached [s].
    pub t: f64,
    /// The step of the snap [s].
    pub dt: f64,
    /// The snap's closing speed [m/s].
    pub speed: f64,
    /// The largest step that samples the snap's crest within 1 % [s].
    pub resolving_dt: f64,
}

/// An unresolved snap of an element: its step [s], closing speed [m/s] and resolving step [s].
#[derive(Debug, Clone, Copy)]
struct SnapAt {
    dt: f64,
    speed: f64,
    resolving_dt: f64,
    /// The snap's estimated tension T* [N].
    estimate: f64,
}

/// The largest tension of an element so far [N], when [s], and the unresolved snap of its
/// own at which it was reached, if any.
#[derive(Debug, Clone, Copy, Default)]
struct ElementTop {
    tension: f64,
    t: f64,
    snap: Option<SnapAt>,
}

impl ElementTop {
    /// The extreme as reached at an unresolved snap of `element` (of `group`), if it was and
    /// the snap's crest T* is at least 1 % of it (a smaller crest cannot move it by more).
    fn extreme(&self, element: usize, group: usize) -> Option<SnapExtreme> {
        let s = self.snap?;
        (s.estimate >= SNAP_EXCESS_WARNING * self.tension).then_some(SnapExtreme {
            element,
            group,
            tension: self.tension,
            t: self.t,
            dt: s.dt,
            speed: s.speed,
            resolving_dt: s.resolving_dt,
        })
    }
}

/// A step's start: positions [m], velocities [m/s] and accelerations [m/s²] of the nodes.
type Start<'a> = (&'a [[f64; 3]], &'a [[f64; 3]], &'a [[f64; 3]]);

/// The largest unresolved snap so far and the largest computed tension.
#[derive(Debug, Clone)]
pub(crate) struct SnapTracker {
    /// Largest element tension over the accepted states [N].
    computed: f64,
    /// The largest unresolved snap (estimate 0 before any).
    worst: SnapResolution,
    /// The elements with one end held, and their groups.
    support: Vec<usize>,
    support_group: Vec<usize>,
    /// Each element's index in `support` (`usize::MAX`: not supported).
    slot: Vec<usize>,
    /// Each supported element's largest tension so far.
    top: Vec<ElementTop>,
    /// Each supported element's unresolved snap in the last accepted step and the one before.
    current: Vec<Option<SnapAt>>,
    previous: Vec<Option<SnapAt>>,
    /// Every unresolved snap (element, group, snap) of the last accepted step and the one
    /// before.
    snapped_now: Vec<(usize, usize, SnapAt)>,
    snapped_before: Vec<(usize, usize, SnapAt)>,
    /// The run's largest tension so far, its element and group, when, and its snap.
    peak: (ElementTop, usize, usize),
    /// Each element's group.
    group_of: Vec<usize>,
    /// Each group's unresolved snaps: their count and largest crest T* [N].
    group_snaps: Vec<(usize, f64)>,
    /// The end of the last accepted step [s].
    t_now: f64,
}

impl SnapTracker {
    /// The tracker of `model`'s cable elements (None without any).
    pub(crate) fn new(model: &Model) -> Option<Self> {
        if model.elements().is_empty() {
            return None;
        }
        let mut slot = vec![usize::MAX; model.elements().len()];
        let (mut support, mut support_group) = (Vec::new(), Vec::new());
        for (i, el) in model.elements().iter().enumerate() {
            if held(model, el.a) != held(model, el.b) {
                slot[i] = support.len();
                support.push(i);
                support_group.push(el.group);
            }
        }
        let n = support.len();
        let group_of: Vec<usize> = model.elements().iter().map(|el| el.group).collect();
        let groups = group_of.iter().map(|g| g + 1).max().unwrap_or(0);
        Some(Self {
            computed: 0.0,
            worst: SnapResolution::default(),
            support,
            support_group,
            slot,
            top: vec![ElementTop::default(); n],
            current: vec![None; n],
            previous: vec![None; n],
            snapped_now: Vec::new(),
            snapped_before: Vec::new(),
            peak: (ElementTop::default(), 0, 0),
            group_of,
            group_snaps: vec![(0, 0.0); groups],
            t_now: 0.0,
        })
    }

    /// Records an accepted state's element tensions [N].
    pub(crate) fn observe(&mut self, tension: &[f64]) {
        let (mut e, mut largest) = (0, f64::NEG_INFINITY);
        for (i, &t) in tension.iter().enumerate() {
            if t > largest {
                (e, largest) = (i, t);
            }
        }
        if largest > self.computed {
            self.computed = largest;
            let snap = self
                .snapped_now
                .iter()
                .chain(&self.snapped_before)
                .find(|s| s.0 == e);
            self.peak = (
                ElementTop {
                    tension: largest,
                    t: self.t_now,
                    snap: snap.map(|s| s.2),
                },
                e,
                snap.map_or(0, |s| s.1),
            );
        }
        for (k, &e) in self.support.iter().enumerate() {
            let top = &mut self.top[k];
            if tension[e] > top.tension {
                *top = ElementTop {
                    tension: tension[e],
                    t: self.t_now,
                    snap: self.current[k].or(self.previous[k]),
                };
            }
        }
    }

    /// Records the snaps of an accepted step of length h [s] from (x_n, v_n) at time t [s] to
    /// (x1, v1); `added` is the nodes' added-mass blocks [kg].
    pub(crate) fn step(
        &mut self,
        model: &Model,
        added: &[[[f64; 3]; 3]],
        (xn, vn, an): Start<'_>,
        (x1, v1): (&[[f64; 3]], &[[f64; 3]]),
        t: f64,
        h: f64,
    ) {
        std::mem::swap(&mut self.current, &mut self.previous);
        self.current.fill(None);
        std::mem::swap(&mut self.snapped_now, &mut self.snapped_before);
        self.snapped_now.clear();
        self.t_now = t + h;
        for (i, el) in model.elements().iter().enumerate() {
            let Some((speed, mr)) = snap(model, el, added, (xn, vn, an), (x1, v1), h) else {
                continue;
            };
            let k = el.ea / el.l0;
            let omega = (k / mr).sqrt();
            if omega * h <= RESOLVED_PHASE {
                continue;
            }
            self.worst.snaps += 1;
            let estimate = speed * (k * mr).sqrt();
            let g = &mut self.group_snaps[el.group];
            g.0 += 1;
            g.1 = g.1.max(estimate);
            let at = SnapAt {
                dt: h,
                speed,
                resolving_dt: RESOLVED_PHASE / omega,
                estimate,
            };
            if let Some(slot) = self.current.get_mut(self.slot[i]) {
                *slot = Some(at);
            }
            self.snapped_now.push((i, el.group, at));
            if estimate > self.worst.estimate {
                self.worst = SnapResolution {
                    snaps: self.worst.snaps,
                    group: el.group,
                    element: i,
                    t,
                    dt: h,
                    speed,
                    estimate,
                    resolving_dt: RESOLVED_PHASE / omega,
                    ..SnapResolution::default()
                };
            }
        }
    }

    /// The run's largest unresolved snap so far, against the largest tension computed so far
    /// (None before any unresolved snap).
    #[cfg(test)]
    pub(crate) fn resolution(&self) -> Option<SnapResolution> {
        let mut r = None;
        self.resolve_into(&mut r);
        r
    }

    /// [`SnapTracker::resolution`] written into `out`, reusing the list of supports that `out`
    /// already holds: called after every accepted step, it allocates only when that list grows.
    pub(crate) fn resolve_into(&self, out: &mut Option<SnapResolution>) {
        if self.worst.estimate <= 0.0 {
            *out = None;
            return;
        }
        let mut support = out.take().map(|r| r.support).unwrap_or_default();
        support.clear();
        support.extend(
            self.support
                .iter()
                .zip(&self.support_group)
                .zip(&self.top)
                .filter_map(|((&element, &group), top)| top.extreme(element, group)),
        );
        // Largest first; equal tensions in element order, so the list is the same at any
        // number of threads.
        support.sort_unstable_by(|a, b| {
            b.tension
                .total_cmp(&a.tension)
                .then(a.element.cmp(&b.element))
        });
        let (top, element, group) = &self.peak;
        let peak_group = self.group_of[*element];
        let (snaps, estimate) = self.group_snaps[peak_group];
        *out = Some(SnapResolution {
            peak: top.extreme(*element, *group),
            peak_group: (snaps > 0).then_some(GroupSnaps {
                group: peak_group,
                snaps,
                estimate,
            }),
            support,
            computed: self.computed,
            excess: if self.computed > 0.0 {
                (self.worst.estimate - self.computed) / self.computed
            } else {
                f64::MAX
            },
            ..self.worst.clone()
        });
    }
}

/// Whether element `el` snapped taut within the step from (x_n, v_n) to (x1, v1) of length
/// h [s]: slack at the start and taut at the end, or slack at both ends but taut at the middle
/// of the nodes' cubic Hermite path, x(h/2) = (x_n + x1)/2 + h/8·(v_n − v1). Then its closing
/// speed v_c [m/s] — the speed at which the start's slack closes under the start's stretch
/// acceleration, or the mean rate over the step if larger (slack to taut), or the reopening
/// rate at the end if larger (taut inside the step only) — and the reduced mass m_r [kg] of its
/// nodes along it (structural plus added; a held node's partner alone).
fn snap(
    model: &Model,
    el: &crate::model::Cable,
    added: &[[[f64; 3]; 3]],
    (xn, vn, an): Start<'_>,
    (x1, v1): (&[[f64; 3]], &[[f64; 3]]),
    h: f64,
) -> Option<(f64, f64)> {
    if el.l0 <= 0.0 || el.ea <= 0.0 {
        return None;
    }
    // Stretch l − L0 and its rate at the step's ends.
    let stretch = |x: &[[f64; 3]], v: &[[f64; 3]]| {
        let d = sub(x[el.b], x[el.a]);
        let l = norm(d);
        let rate = if l > 0.0 {
            dot(d, sub(v[el.b], v[el.a])) / l
        } else {
            0.0
        };
        (l - el.l0, rate)
    };
    let (s0, r0) = stretch(xn, vn);
    if s0 >= 0.0 {
        return None;
    }
    // The speed at which the slack s0 closes under the start's stretch acceleration
    // s̈ = (d·Δa + |Δv|² − ṡ²)/l held constant: √(ṡ0² + 2·s̈0·|s0|).
    let d = sub(xn[el.b], xn[el.a]);
    let dv = sub(vn[el.b], vn[el.a]);
    let l = norm(d);
    let accel = if l > 0.0 {
        (dot(d, sub(an[el.b], an[el.a])) + dot(dv, dv) - r0 * r0) / l
    } else {
        0.0
    };
    let closing = (r0 * r0 + 2.0 * accel * (-s0)).max(0.0).sqrt();
    let (s1, r1) = stretch(x1, v1);
    let speed = if s1 > 0.0 {
        // Slack to taut: it closed during the step at least at the mean rate.
        closing.max((s1 - s0) / h)
    } else {
        let mid = |n: usize| {
            [0, 1, 2].map(|k| 0.5 * (xn[n][k] + x1[n][k]) + 0.125 * h * (vn[n][k] - v1[n][k]))
        };
        if norm(sub(mid(el.b), mid(el.a))) <= el.l0 {
            return None;
        }
        // Taut inside the step only: as fast as it closed or reopened.
        closing.max(-r1)
    };
    if !(speed > 0.0) {
        return None;
    }
    let d = sub(x1[el.b], x1[el.a]);
    let l = norm(d);
    if l <= 0.0 {
        return None;
    }
    let u = [d[0] / l, d[1] / l, d[2] / l];
    let along = |n: usize| {
        let a: f64 = added.get(n).map_or(0.0, |m| {
            (0..3)
                .map(|p| (0..3).map(|q| u[p] * m[p][q] * u[q]).sum::<f64>())
                .sum()
        });
        model.lumped_mass[n] + a
    };
    let (ma, mb) = (along(el.a), along(el.b));
    let mr = match (held(model, el.a), held(model, el.b)) {
        (true, true) => return None,
        (true, false) => mb,
        (false, true) => ma,
        (false, false) => ma * mb / (ma + mb),
    };
    (mr > 0.0).then_some((speed, mr))
}

/// Whether all three coordinates of node `n` are held.
fn held(model: &Model, n: usize) -> bool {
    (0..3).all(|k| model.is_constrained(n, k))
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CableSection, Dofs, Environment, ModelBuilder, UnstretchedLength};

    /// Adds a rope of L0 = 1 m in its own group `name`, from a held node at (0, y, 0) to a free
    /// 10 kg node at (0.9, y, 0) (slack).
    fn add_rope(b: &mut ModelBuilder, name: &str, y: f64) {
        let g = b.add_group(name, CableSection::new(1e5, 1e-6)).unwrap();
        let a = b.add_node([0.0, y, 0.0]).unwrap();
        let n = b.add_node([0.9, y, 0.0]).unwrap();
        b.add_cable(a, n, g, UnstretchedLength::Given(1.0)).unwrap();
        b.add_point_body(crate::PointBody {
            node: n,
            mass: 10.0,
            force: [0.0; 3],
            seabed_stiffness: 0.0,
        })
        .unwrap();
        b.fix(a, Dofs::ALL).unwrap();
    }

    /// One rope (see [`add_rope`]).
    fn model() -> Model {
        let mut b = ModelBuilder::new(Environment::default());
        add_rope(&mut b, "rope", 0.0);
        b.build().unwrap()
    }

    #[test]
    fn a_snap_between_two_slack_ends_is_seen_at_the_middle_of_the_step() {
        let m = model();
        let el = m.elements()[0];
        let x = [[0.0; 3], [0.9, 0.0, 0.0]];
        let z = [[0.0; 3]; 2];
        let h = 0.1;
        // Out at 6 m/s, back at 6 m/s: slack at both ends, but the cubic path's middle is at
        // 0.9 + h/8·12 = 1.05 m > L0.
        let (vn, v1) = ([[0.0; 3], [6.0, 0.0, 0.0]], [[0.0; 3], [-6.0, 0.0, 0.0]]);
        let (speed, mr) = snap(&m, &el, &[], (&x, &vn, &z), (&x, &v1), h).expect("a snap");
        assert_eq!(speed, 6.0);
        // The held node does not move: the free node's mass (10 kg point + a negligible rope).
        assert!((mr - 10.0).abs() < 1e-5, "{mr}");
        // At 3 m/s the middle is at 1.0 − 0.025 m: no snap.
        let (vn, v1) = ([[0.0; 3], [3.0, 0.0, 0.0]], [[0.0; 3], [-3.0, 0.0, 0.0]]);
        assert!(snap(&m, &el, &[], (&x, &vn, &z), (&x, &v1), h).is_none());
        // Slack to taut: the larger of the closing speed and the mean rate.
        let x1 = [[0.0; 3], [1.01, 0.0, 0.0]];
        let (vn, v1) = ([[0.0; 3], [0.5, 0.0, 0.0]], [[0.0; 3], [0.0; 3]]);
        let (speed, _) = snap(&m, &el, &[], (&x, &vn, &z), (&x1, &v1), h).expect("a snap");
        assert!((speed - 1.1).abs() < 1e-12, "{speed}");
        // Accelerated at 10 m/s² over the 0.1 m of slack: √(0.5² + 2·10·0.1) = 1.5 m/s.
        let an = [[0.0; 3], [10.0, 0.0, 0.0]];
        let (speed, _) = snap(&m, &el, &[], (&x, &vn, &an), (&x1, &v1), h).expect("a snap");
        assert!((speed - 1.5).abs() < 1e-12, "{speed}");
        // Taut at the start: not a snap of this step.
        assert!(snap(&m, &el, &[], (&x1, &vn, &z), (&x1, &v1), h).is_none());
    }

    /// The rope's held end makes it a support element: its largest tension, reached in the
    /// step of an unresolved snap (ω·Δt = 100 rad/s · 0.1 s) or the step after, is reported,
    /// as the run's largest, until a larger tension without a snap replaces it; a snap whose
    /// crest T* is below 1 % of the extreme is not.
    #[test]
    fn a_support_extreme_reached_at_an_unresolved_snap_is_reported() {
        let m = model();
        let mut tr = SnapTracker::new(&m).expect("a cable");
        let z = [[0.0; 3]; 2];
        let h = 0.1;
        let slack = [[0.0; 3], [0.9, 0.0, 0.0]];
        let taut = [[0.0; 3], [1.01, 0.0, 0.0]];
        let out = [[0.0; 3], [1.0, 0.0, 0.0]];
        // Slack to taut at 1.1 m/s: T* = 1.1·√(1e5·10) = 1 100 N.
        tr.step(&m, &[], (&slack, &out, &z), (&taut, &z), 0.0, h);
        tr.observe(&[1000.0]);
        let r = tr.resolution().expect("a snap");
        assert_eq!(r.support.len(), 1);
        let s = r.support[0];
        assert_eq!((s.element, s.tension, s.dt), (0, 1000.0, h));
        // It is also the run's largest tension.
        assert_eq!(r.peak, Some(s));
        assert!(
            (s.t - h).abs() < 1e-12 && (s.speed - 1.1).abs() < 1e-12,
            "{s:?}"
        );
        // The step after the snap: a new largest tension there is still the snap's.
        tr.step(&m, &[], (&taut, &z, &z), (&taut, &z), h, h);
        tr.observe(&[1200.0]);
        let s = tr.resolution().unwrap().support[0];
        assert_eq!(s.tension, 1200.0);
        assert!((s.t - 2.0 * h).abs() < 1e-12);
        // Two steps after: a larger tension is a resolved extreme.
        tr.step(&m, &[], (&taut, &z, &z), (&taut, &z), 2.0 * h, h);
        tr.observe(&[1500.0]);
        let r = tr.resolution().unwrap();
        assert!(r.support.is_empty() && r.peak.is_none(), "{r:?}");
        // A snap closing 0.11 mm in a step (1.1 mm/s, T* = 1.1 N) under a 1 000 N extreme.
        let mut tr = SnapTracker::new(&m).unwrap();
        let barely = [[0.0; 3], [0.9999, 0.0, 0.0]];
        let just = [[0.0; 3], [1.00001, 0.0, 0.0]];
        tr.step(&m, &[], (&barely, &z, &z), (&just, &z), 0.0, h);
        tr.observe(&[1000.0]);
        let r = tr.resolution().expect("an unresolved snap");
        assert!((r.estimate - 1.1).abs() < 1e-6, "{}", r.estimate);
        assert!(r.support.is_empty() && r.peak.is_none(), "{r:?}");
    }

    /// Two ropes (see [`add_rope`]): group "a" at y = 0, then group "b" at y = 5 m.
    fn two_groups() -> Model {
        let mut b = ModelBuilder::new(Environment::default());
        add_rope(&mut b, "a", 0.0);
        add_rope(&mut b, "b", 5.0);
        b.build().unwrap()
    }

    /// The unresolved snaps of the group that carries the run's largest tension are counted
    /// with their largest crest; those of another group are not its.
    #[test]
    fn the_snaps_of_the_largest_tension_group_are_counted() {
        let m = two_groups();
        let z = [[0.0; 3]; 4];
        let h = 0.1;
        let slack = [[0.0; 3], [0.9, 0.0, 0.0], [0.0, 5.0, 0.0], [0.9, 5.0, 0.0]];
        let taut = [
            [0.0; 3],
            [1.01, 0.0, 0.0],
            [0.0, 5.0, 0.0],
            [1.01, 5.0, 0.0],
        ];
        // Group "b" snaps at 1.1 m/s (T* = 1 100 N), group "a" does not move.
        let vb = [[0.0; 3], [0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]];
        let only_b = [[0.0; 3], [0.9, 0.0, 0.0], [0.0, 5.0, 0.0], [1.01, 5.0, 0.0]];
        let mut tr = SnapTracker::new(&m).unwrap();
        tr.step(&m, &[], (&slack, &vb, &z), (&only_b, &z), 0.0, h);
        // The largest tension is group "a"'s (element 0): it had no snap.
        tr.observe(&[2000.0, 1000.0]);
        assert_eq!(tr.resolution().expect("a snap").peak_group, None);
        // Both snap, "a" at 0.5 m/s (T* = 500 N) and "b" again; then "a" at 1.1 m/s.
        let v = [[0.0; 3], [0.4, 0.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0]];
        tr.step(&m, &[], (&slack, &v, &z), (&taut, &z), h, h);
        let v = [[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], [0.0; 3]];
        tr.step(&m, &[], (&slack, &v, &z), (&taut, &z), 2.0 * h, h);
        tr.observe(&[2000.0, 1000.0]);
        let g = tr
            .resolution()
            .unwrap()
            .peak_group
            .expect("group a snapped");
        assert_eq!((g.group, g.snaps), (m.elements()[0].group, 2));
        assert!((g.estimate - 1100.0).abs() < 1e-3, "{g:?}");
    }
}
