//! Step control: the accepted step with its landing on output times, halving on a failed
//! attempt and regrowth after easy steps, what the control did (`StepControl`) and the time
//! step's error indicators (docs/theory/fem.md#step-control, #time-step-error-indicator).

use super::DynamicSolver;
use super::energy::Energies;
use super::newton::Attempt;
use crate::cable::CableEval;
use crate::error::{FemError, Result};
use crate::failure::{FailureKind, FailureReason};
use crate::loads::LoadProvider;
use serde::{Deserialize, Serialize};

/// A landing step within this fraction of Δt of the step itself is taken as Δt (the
/// difference is the round-off of t_out − t).
const LANDING_ROUNDOFF: f64 = 1e-9;

/// What one accepted step did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// Time reached [s].
    pub t: f64,
    /// Step used [s].
    pub dt: f64,
    /// Newton iterations (factorisations) of the accepted attempt (0 for explicit schemes).
    pub iterations: usize,
    /// Failed attempts (step halvings) before acceptance.
    pub retries: usize,
    /// ‖r_k‖/F_ref per iteration of the accepted attempt.
    pub residual_history: Vec<f64>,
    /// Observed order log(r_{k+1}/F)/log(r_k/F) of the last two iterations, if available.
    pub convergence_order: Option<f64>,
    /// The step landed on an output time (a multiple of `output_interval`) or the end.
    pub output_time: bool,
    /// Energy balance.
    pub energies: Energies,
}

/// What the step control did: every halving with its time and reason, and the regrowths.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StepControl {
    /// Steps halved (failed attempts that were retried with half the step).
    pub halvings: usize,
    /// Times the step was doubled back towards the nominal dt.
    pub regrowths: usize,
    /// Smallest step tried [s] (0 before any halving).
    pub smallest_dt: f64,
    /// Halvings per kind of reason, in order of first occurrence.
    pub reasons: Vec<(FailureKind, usize)>,
    /// The first [`StepControl::MAX_EVENTS`] halvings.
    pub events: Vec<StepEvent>,
    /// Largest local time-discretisation error estimate of a step [m]
    /// (docs/theory/fem.md#time-step-error-indicator).
    pub max_local_error: f64,
    /// Sum of the local error estimates over the accepted steps [m]: a bound-like estimate of
    /// the position error the time step has accumulated.
    pub sum_local_error: f64,
    /// Largest displacement of a free node from where the integration started [m].
    pub max_displacement: f64,
    /// Peak element tension T_pk = max_e T_e after each accepted step, the start included [N]
    /// (docs/theory/fem.md#time-step-error-indicator).
    #[serde(skip)]
    pub peak_tensions: Vec<f64>,
    /// The element carrying each of [`StepControl::peak_tensions`] (may be shorter: then the
    /// element is not known).
    #[serde(skip)]
    pub peak_elements: Vec<usize>,
    /// What the extreme control did, with `extreme_tolerance` set
    /// (docs/theory/fem.md#extremes-to-a-tolerance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extremes: Option<super::ExtremeResolution>,
    /// The seabed contact's landings and lift-offs and how well the step resolves them, with a
    /// seabed the nodes can touch (docs/theory/fem.md#seabed-contact-resolution).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seabed_contact: Option<super::ContactResolution>,
    /// The worst snap of a slack element within a single step that the step does not resolve
    /// (docs/theory/fem.md#snap-resolution).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub snaps: Option<super::SnapResolution>,
    /// The step-to-step ripple of the peak tension near its top, once the run is over
    /// ([`StepControl::step_ripple`]; docs/theory/fem.md#step-ripple-indicator).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_ripple: Option<super::StepRipple>,
}

impl StepControl {
    /// How well the time step resolves the extremes of the peak tension (0 error when it did
    /// not vary); see [`TensionResolution`].
    pub fn peak_tension_resolution(&self) -> TensionResolution {
        let t = &self.peak_tensions;
        let (lo, hi) = t
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        let amplitude = 0.5 * (hi - lo);
        if t.len() < 2 || amplitude <= 0.0 {
            return TensionResolution::default();
        }
        // Steps from or into the top quarter of the range: where a sampled maximum is formed.
        let top = hi - 0.5 * amplitude;
        let (jump, at) = t
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[0] >= top || w[1] >= top)
            .map(|(i, w)| ((w[1] - w[0]).abs(), if w[1] >= w[0] { i + 1 } else { i }))
            .fold(
                (0.0, None),
                |(m, a), (j, i)| if j > m { (j, Some(i)) } else { (m, a) },
            );
        // A sine's slope in its top quarter is at most cos 30° of its slope at the mean.
        let r = jump / (amplitude * 0.75f64.sqrt());
        TensionResolution {
            jump,
            range: [lo, hi],
            error: r * r / 8.0 * amplitude / hi,
            element: at.and_then(|i| self.peak_elements.get(i).copied()),
        }
    }

    /// The accumulated time-step error estimate relative to the largest displacement (0 when
    /// nothing moved).
    pub fn relative_time_error(&self) -> f64 {
        if self.max_displacement > 0.0 {
            self.sum_local_error / self.max_displacement
        } else {
            0.0
        }
    }
}

/// The time step's resolution of the peak tension (docs/theory/fem.md#time-step-error-indicator).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TensionResolution {
    /// Largest one-step change of the peak tension among the steps in the top quarter of its
    /// range [N].
    pub jump: f64,
    /// Smallest and largest peak tension [N].
    pub range: [f64; 2],
    /// Estimated relative error of the largest tension, ε_T = r²/8 · A/T_max, with A the half
    /// range and r = jump/(A·cos 30°) the phase step ωΔt of a sine of amplitude A whose slope
    /// in its top quarter is at most cos 30° of its largest.
    pub error: f64,
    /// The element carrying the peak tension at the higher end of that largest step change,
    /// when known: the member whose tension the step missed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub element: Option<usize>,
}

/// One halving.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepEvent {
    /// Time the step started from [s].
    pub t: f64,
    /// Step that failed [s].
    pub dt: f64,
    /// Step tried next [s].
    pub next_dt: f64,
    /// Why it failed (the reason's message).
    pub reason: String,
    /// The kind of reason.
    pub kind: FailureKind,
}

impl StepControl {
    /// Halvings kept in `events`.
    pub const MAX_EVENTS: usize = 100;

    fn record(&mut self, t: f64, dt: f64, next_dt: f64, reason: &FailureReason) {
        self.halvings += 1;
        self.smallest_dt = if self.smallest_dt > 0.0 {
            self.smallest_dt.min(next_dt)
        } else {
            next_dt
        };
        let kind = reason.kind();
        match self.reasons.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, n)) => *n += 1,
            None => self.reasons.push((kind, 1)),
        }
        if self.events.len() < Self::MAX_EVENTS {
            self.events.push(StepEvent {
                t,
                dt,
                next_dt,
                reason: reason.to_string(),
                kind,
            });
        }
    }
}

impl DynamicSolver<'_> {
    /// Takes one accepted step (halving Δt on failure down to `dt_min`), landing on output
    /// times and on t_end. Returns an error if the step cannot be completed; the state is then
    /// the last converged one.
    pub fn step<P: LoadProvider + ?Sized>(&mut self, provider: &mut P) -> Result<StepReport> {
        if self.is_finished() {
            return Err(FemError::InvalidModel(format!(
                "step requested after t_end = {}",
                self.st.t_end
            )));
        }
        // Load data fixed within the step (wake membership) follows the accepted state.
        crate::loads::accept_state(provider, self.state.t, &self.state.x)?;
        // The rods' reference frames follow the accepted state too (docs/theory/fem.md#rod).
        self.sys.accept_rod_frames(self.model, &self.state.x);
        // So do the rigid bodies' (docs/theory/fem.md#rigid-bodies).
        self.sys.accept_body_frames(self.model, &self.state.x);
        let dt_min = self.st.dt_min.unwrap_or(self.st.dt / 1024.0);
        let t = self.state.t;
        let mut retries = 0;
        loop {
            let mut h = self.dt_cur;
            let mut target = self.st.t_end;
            if let Some(oi) = self.st.output_interval {
                let k = ((t + 1e-9 * self.st.dt) / oi).floor() + 1.0;
                target = target.min(k * oi);
            }
            let mut landed = false;
            // Land on the target when within 1e-6·dt of it: a remaining sliver of round-off
            // size would be a step whose (x1 − x_n)/h is all round-off.
            if t + h >= target - 1e-6 * self.st.dt {
                // A landing that differs from the step by round-off only (t_out − t ≠ Δt
                // in the last bits) keeps Δt, so the step, its tangent and the kept factor
                // are those of any other step; the clock is set to t_out exactly below.
                if (target - t - h).abs() > LANDING_ROUNDOFF * self.st.dt {
                    h = target - t;
                }
                landed = true;
            }
            let outcome = self.attempt(provider, h).and_then(|ok| {
                match self.guard(h).or_else(|| self.extreme_guard(h, dt_min)) {
                    Some(reason) => Err(Attempt {
                        reason,
                        history: ok.1.clone(),
                    }),
                    None => Ok(ok),
                }
            });
            match outcome {
                Ok((iters, hist)) => {
                    if hist.len() >= 2 && hist[0] > 0.0 {
                        self.first_contraction = hist[1] / hist[0];
                    }
                    self.full_newton = false;
                    self.track_time_error(h);
                    // Landings and lift-offs (docs/theory/fem.md#seabed-contact-resolution).
                    if let (Some(tracker), Some(out)) =
                        (self.contact.as_ref(), self.control.seabed_contact.as_mut())
                    {
                        tracker.step(
                            self.model,
                            &self.scheme,
                            &self.sys.added,
                            (&self.state.x, &self.state.v),
                            (&self.x1, &self.v1),
                            h,
                            out,
                        );
                    }
                    // Snaps of slack elements (docs/theory/fem.md#snap-resolution).
                    if let Some(snaps) = self.snaps.as_mut() {
                        snaps.step(
                            self.model,
                            &self.sys.added,
                            (&self.state.x, &self.state.v, &self.state.a),
                            (&self.x1, &self.v1),
                            t,
                            h,
                        );
                    }
                    self.clamp = false;
                    self.total_iterations += iters;
                    self.n_steps += 1;
                    std::mem::swap(&mut self.state.x, &mut self.x1);
                    std::mem::swap(&mut self.state.v, &mut self.v1);
                    std::mem::swap(&mut self.state.a, &mut self.a1);
                    self.state.t = if landed { target } else { t + h };
                    self.scheme.accept(self.model, &self.state.x, self.state.t);
                    // x1 now holds x_n (for the work increments).
                    self.accept_bookkeeping(h, false);
                    if let Some(snaps) = self.snaps.as_mut() {
                        snaps.observe(&self.outputs.tension);
                        snaps.resolve_into(&mut self.control.snaps);
                    }
                    if let Some(c) = self.extremes.as_mut() {
                        c.accept(
                            self.model,
                            &self.outputs.tension,
                            &self.state.x,
                            &self.state.v,
                        );
                    }
                    // Easy step: few factorisations (= iterations with full Newton).
                    if self.attempt_factorisations <= 4 {
                        self.good_steps += 1;
                        if self.good_steps >= 4 && self.dt_cur < self.st.dt {
                            self.dt_cur = (2.0 * self.dt_cur).min(self.st.dt);
                            self.good_steps = 0;
                            self.control.regrowths += 1;
                        }
                    } else {
                        self.good_steps = 0;
                    }
                    let order = if hist.len() >= 3 {
                        let k = hist.len() - 1;
                        let (a, b) = (hist[k - 1], hist[k]);
                        (a > 0.0 && b > 0.0 && a < 1.0).then(|| b.ln() / a.ln())
                    } else {
                        None
                    };
                    let on_output = self.st.output_interval.is_none() || landed;
                    return Ok(StepReport {
                        t: self.state.t,
                        dt: h,
                        iterations: iters,
                        retries,
                        residual_history: hist,
                        convergence_order: order,
                        output_time: on_output,
                        energies: self.energies,
                    });
                }
                Err(fail) => {
                    retries += 1;
                    self.good_steps = 0;
                    self.lu_valid = false;
                    // A coarse crest is the step's length, not its solve: straight to halving.
                    let resolved_solve = fail.reason.kind() == FailureKind::ExtremeUnresolved;
                    if !resolved_solve && !self.full_newton && self.attempt_stale_solves > 0 {
                        // Modified Newton failed: retry the same step with full Newton first.
                        self.full_newton = true;
                        continue;
                    }
                    // The clamp changes the tangent only where a slack element pushes (the
                    // scheme says where that can be); a retry that cannot differ costs max_iter.
                    let scheme = &self.scheme;
                    let matters = |c: &CableEval| scheme.clamp_matters(c);
                    let sys = &self.sys;
                    if !resolved_solve
                        && !self.clamp
                        && (sys.cable.iter().any(matters) || sys.net_twines().any(matters))
                    {
                        // Retry the same step with T ≥ 0 in the slack elements' geometric term.
                        self.clamp = true;
                        continue;
                    }
                    self.clamp = false;
                    self.full_newton = false;
                    self.dt_cur = 0.5 * h.min(self.dt_cur);
                    self.control.record(t, h, self.dt_cur, &fail.reason);
                    if self.dt_cur < dt_min {
                        return Err(self.step_failure(provider, h, dt_min, fail));
                    }
                }
            }
        }
    }

    /// The local error estimate of an accepted step (Zienkiewicz and Xie): the Newmark family's
    /// leading truncation term e = |β − 1/6|·Δt²·‖a_{n+1} − a_n‖_∞ over the free DOFs, with
    /// β = (1 + α)²/4 (β = 1/4 for the midpoint rule), and the largest displacement so far.
    fn track_time_error(&mut self, h: f64) {
        let beta = self.scheme.error_beta();
        let (mut da, mut disp) = (0.0f64, 0.0f64);
        for &gd in &self.sys.dof_of_free {
            let (i, k) = (gd / 3, gd % 3);
            da = da.max((self.a1[i][k] - self.state.a[i][k]).abs());
            disp = disp.max((self.x1[i][k] - self.x_start[i][k]).abs());
        }
        let e = (beta - 1.0 / 6.0).abs() * h * h * da;
        let c = &mut self.control;
        c.max_local_error = c.max_local_error.max(e);
        c.sum_local_error += e;
        c.max_displacement = c.max_displacement.max(disp);
    }

    fn step_failure<P: LoadProvider + ?Sized>(
        &mut self,
        _provider: &mut P,
        h: f64,
        dt_min: f64,
        fail: Attempt,
    ) -> FemError {
        let n = self.model.n_nodes();
        let mut node_r = vec![0.0; n];
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            node_r[gd / 3] += self.r[f] * self.r[f];
        }
        let mut worst = (0usize, -1.0f64);
        for (i, r) in node_r.iter().enumerate() {
            let r = if r.is_finite() {
                r.sqrt()
            } else {
                f64::INFINITY
            };
            if r > worst.1 {
                worst = (i, r);
            }
        }
        let mut maxs = (0usize, f64::NEG_INFINITY);
        let mut mins = (0usize, f64::INFINITY);
        for (i, c) in self.sys.cable.iter().enumerate() {
            if c.strain > maxs.1 {
                maxs = (i, c.strain);
            }
            if c.strain < mins.1 {
                mins = (i, c.strain);
            }
        }
        FemError::StepFailed(Box::new(crate::error::StepFailure {
            t: self.state.t,
            dt: h,
            dt_min,
            reason: fail.reason,
            worst_node: worst.0,
            worst_position: self.x1[worst.0],
            worst_residual: worst.1,
            max_strain_element: maxs.0,
            max_strain: maxs.1,
            min_strain_element: mins.0,
            min_strain: mins.1,
            history: fail.history,
            scheme: self.scheme.kind(),
        }))
    }
}
