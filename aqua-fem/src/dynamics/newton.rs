//! The Newton loop of an implicit step, one for every implicit scheme: modified Newton with a
//! kept factor, a lazy convergence check, inexact solves with a forcing term, backtracking
//! across kinks of the force law and line relaxation after each update
//! (docs/theory/fem.md#hht-alpha, #convergence-check, #backtracking, #line-relaxation).

use super::DynamicSolver;
use crate::error::Result;
use crate::failure::FailureReason;
use crate::line_relaxation::StepKinematics;
use crate::loads::LoadProvider;
use crate::system::{EvalOptions, NONE, System};

/// A Newton update's linear solve may leave a residual of this fraction of the Newton
/// residual tolerance (inexact Newton; docs/theory/fem.md#sparse-linear-algebra).
const LINEAR_FORCING: f64 = 1e-2;

/// Fraction of the predicted nonlinear remainder that an update's solve may leave while that
/// remainder is above the Newton tolerance (docs/theory/fem.md#sparse-linear-algebra).
const EW_FRACTION: f64 = 0.1;

/// Contraction ‖r_k‖/‖r_{k−1}‖ below which Newton counts as in its quadratic regime, where the
/// forcing term applies.
const EW_REGIME: f64 = 0.1;

/// Lines are relaxed down to this fraction of the Newton tolerance's force
/// (docs/theory/fem.md#line-relaxation).
const LINE_FLOOR: f64 = 1e-2;

/// Smallest fraction of a Newton update that backtracking tries.
const MIN_STEP_SCALE: f64 = 1.0 / 16.0;

/// Why an attempt failed, with its residual history.
pub(super) struct Attempt {
    pub(super) reason: FailureReason,
    pub(super) history: Vec<f64>,
}

impl DynamicSolver<'_> {
    /// One Newton solve of the step's residual M·a + w·q_{n+1} + (1 − w)·q_n = 0 for a step h,
    /// with the scheme's kinematics, Jacobian coefficients and weight w. On success x1, v1, a1 hold the new
    /// state and `sys` its evaluation.
    pub(super) fn attempt<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        h: f64,
    ) -> std::result::Result<(usize, Vec<f64>), Attempt> {
        let model = self.model;
        let t1 = self.state.t + h;
        let n = model.n_nodes();
        self.scheme.begin(model, &self.state.x, self.state.t);
        // Predictor.
        for i in 0..n {
            for k in 0..3 {
                let (x, v, a) = (self.state.x[i][k], self.state.v[i][k], self.state.a[i][k]);
                self.x1[i][k] = x + h * v + 0.5 * h * h * a;
            }
        }
        model.apply_constraints(t1, 1.0, &mut self.x1, &mut self.v1, &mut self.a1);
        // ∂r/∂x_{n+1} = m·M + k·K + c·C, the evaluation time and the weight of q_{n+1} in the
        // residual are the scheme's.
        let coef = self.scheme.coef(h);
        let body_noise = self.body_round_off(coef.m);
        let t_eval = self.scheme.eval_time(self.state.t, h);
        let wq = self.scheme.residual_weight();
        let wprev = 1.0 - wq;
        let o = self.opts(Some(coef), t_eval);
        let o_res = self.opts(None, t_eval);
        let reuse = if self.full_newton {
            1
        } else {
            self.st.reuse_factor.max(1)
        };
        if self.lu_h != h {
            self.lu_valid = false;
            // A new Δt changes the tangent's mass and damping terms by its square.
            self.sys.require_fresh_factor();
        }
        let mut rn_prev = f64::INFINITY;
        self.attempt_factorisations = 0;
        self.attempt_stale_solves = 0;
        let xtol = 1e-6 * model.mean_length;
        let mut hist = Vec::new();
        let mut dx_prev = f64::INFINITY;
        let mut r0 = f64::NAN;
        // Scale of the last update applied (0: none yet) and how often the residual rose.
        let mut step_scale = 0.0f64;
        let mut increases = 0usize;
        // The last update was made with a fresh J and is expected to end the step.
        let mut expect_done = false;
        let fail = |reason: FailureReason, hist: &Vec<f64>| Attempt {
            reason,
            history: hist.clone(),
        };
        for it in 0..self.st.max_iter {
            self.scheme.kinematics(
                h,
                model,
                &self.sys,
                (&self.state.x, &self.state.v, &self.state.a),
                &self.x1,
                &mut self.v1,
                &mut self.a1,
            );
            // Modified Newton: keep the stored factorisation while it is fresh enough; then
            // the Jacobian need not be assembled.
            let mut refactor = !(reuse > 1 && self.lu_valid && self.lu_uses < reuse);
            // When the last update is expected to have converged the step, the evaluation
            // forms no Jacobian: the check that ends the step is the simplified Newton
            // correction with the factor just used (docs/theory/fem.md#convergence-check).
            let lazy = refactor && expect_done && self.lu_valid && self.lu_h == h;
            let oe = if refactor && !lazy { &o } else { &o_res };
            if let Err(e) = self.evaluate_at_step(provider, oe) {
                return Err(fail(e.into(), &hist));
            }
            let mut rn = 0.0;
            for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                let (i, k) = (gd / 3, gd % 3);
                let r = self.sys.ma[i][k] + wq * self.sys.q[i][k] + wprev * self.q_prev[i][k];
                self.r[f] = r;
                rn += r * r;
            }
            let rn = rn.sqrt();
            let f_ref = self.f_ref();
            hist.push(rn / f_ref);
            if !rn.is_finite() {
                return Err(fail(FailureReason::NonFiniteResidual, &hist));
            }
            if it == 0 {
                r0 = rn;
            } else if rn > 1e4 * r0 && rn > self.st.tol * f_ref {
                return Err(fail(FailureReason::ResidualGrew, &hist));
            }
            let tol = (self.st.tol * f_ref).max(body_noise);
            if lazy {
                if rn <= tol {
                    refactor = false;
                } else if let Err(e) = self.evaluate_at_step(provider, &o) {
                    return Err(fail(e.into(), &hist));
                }
            }
            let max_strain = self.st.max_strain;
            let strain_check = |sys: &System, hist: &Vec<f64>| match sys
                .cable
                .iter()
                .chain(sys.net_twines())
                .find(|c| c.strain.abs() > max_strain)
            {
                Some(c) => Err(Attempt {
                    reason: FailureReason::StrainLimit {
                        strain: c.strain,
                        max_strain,
                    },
                    history: hist.clone(),
                }),
                None => Ok(()),
            };
            if it > 0 && rn <= tol && dx_prev <= xtol {
                strain_check(&self.sys, &hist)?;
                return self.finish_attempt(provider, t1, it, hist);
            }
            if rn > rn_prev && step_scale > 0.0 {
                increases += 1;
                if increases >= 2 && step_scale > MIN_STEP_SCALE {
                    // The residual rose again: a cycle across a kink of the force law (seabed
                    // touchdown, slack switch). Backtrack along the last update instead of
                    // taking another full step (docs/theory/fem.md#backtracking).
                    let back = 0.5 * step_scale;
                    for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                        self.x1[gd / 3][gd % 3] -= back * self.dx[f];
                    }
                    step_scale -= back;
                    dx_prev *= 0.5;
                    continue;
                }
            }
            if !refactor && !lazy && it > 0 && rn > 0.5 * rn_prev {
                // Contraction below 2×: re-form J at this iterate.
                refactor = true;
                if let Err(e) = self.evaluate_at_step(provider, &o) {
                    return Err(fail(e.into(), &hist));
                }
            }
            if refactor {
                self.lu_valid = false;
                if let Err(e) = self.sys.factorize() {
                    return Err(fail(e.into(), &hist));
                }
                self.lu_valid = true;
                self.lu_h = h;
                self.lu_uses = 0;
                self.attempt_factorisations += 1;
            }
            if lazy && !refactor {
                self.stale_checks += 1;
            } else if !refactor {
                self.attempt_stale_solves += 1;
            }
            self.lu_uses += 1;
            // The last contraction q, and the remainder it predicts in Newton's quadratic regime
            // (q ≤ EW_REGIME, i.e. at least 10×; otherwise nothing is predicted).
            let q = if it == 0 {
                self.first_contraction
            } else {
                rn / rn_prev
            };
            let predicted = if q <= EW_REGIME {
                rn * if it == 0 { q } else { q * q }
            } else {
                0.0
            };
            rn_prev = rn;
            for f in 0..self.r.len() {
                self.dx[f] = -self.r[f];
            }
            // With the residual already within tolerance this solve only checks that the
            // Newton correction is below `xtol` (it is not applied then), and the symmetric
            // refinement may stop as soon as that is certain.
            let bound = (rn <= tol).then_some(xtol);
            // Inexact Newton with a forcing term in the manner of Eisenstat and Walker: while
            // the update will leave a nonlinear remainder above tol anyway (predicted from the
            // last contraction, quadratic model), its solve need only reach a tenth of that
            // remainder (docs/theory/fem.md#sparse-linear-algebra); with q ≤ EW_REGIME that is
            // never looser than 1 % of ‖r‖. Full Newton only: the quadratic model does not
            // describe modified Newton.
            let floor = if reuse == 1 && predicted > tol {
                (EW_FRACTION * predicted).max(LINEAR_FORCING * tol)
            } else {
                LINEAR_FORCING * tol
            };
            let settled = match self.sys.solve_within(&mut self.dx, floor, bound) {
                Ok(settled) => settled,
                Err(e) => return Err(fail(e.into(), &hist)),
            };
            let dinf = self.dx.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if settled || (rn <= tol && dinf <= xtol) {
                strain_check(&self.sys, &hist)?;
                return self.finish_attempt(provider, t1, it + 1, hist);
            }
            let relax = refactor && self.relax_lines && self.lines.n_lines() > 0;
            if relax {
                self.x_iter.clone_from(&self.x1);
            }
            for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                self.x1[gd / 3][gd % 3] += self.dx[f];
            }
            step_scale = 1.0;
            dx_prev = dinf;
            expect_done = refactor && (rn <= tol || (q <= EW_REGIME && predicted <= tol));
            if relax {
                // Carry slack-to-taut switches along the lines before the next evaluation
                // (docs/theory/fem.md#line-relaxation).
                let (x_eval, v_eval) = self.scheme.evaluation_state(&self.x_iter, &self.v1);
                let kin = StepKinematics {
                    scheme: &self.scheme,
                    h,
                    xn: &self.state.x,
                    vn: &self.state.v,
                    an: &self.state.a,
                    x_eval,
                    v_eval,
                    coef,
                    weight: wq,
                    a_k: self.st.rayleigh[1],
                    clamp: self.clamp,
                };
                let moved = self.lines.relax(
                    model,
                    &self.sys,
                    &kin,
                    &self.x_iter,
                    &mut self.x1,
                    LINE_FLOOR * tol,
                );
                dx_prev = dx_prev.max(moved);
                if let Some(front) = self.scheme.front_limit()
                    && self.lines.last_front > front
                {
                    // The plain Newton iteration would have failed here: for HHT-α that
                    // failure, and the halving it forces, is what resolves the event
                    // (docs/theory/fem.md#line-relaxation-hht).
                    return Err(fail(FailureReason::LineFront { limit: front }, &hist));
                }
            }
        }
        Err(fail(
            FailureReason::NoConvergence {
                iterations: self.st.max_iter,
            },
            &hist,
        ))
    }

    /// Evaluates the step's equations where the scheme says (docs/theory/fem.md#hht-alpha,
    /// #energy-consistent-midpoint).
    fn evaluate_at_step<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        o: &EvalOptions,
    ) -> Result<()> {
        self.scheme.evaluate(
            &mut self.sys,
            self.model,
            provider,
            (&self.state.x, &self.x1, &self.v1, &self.a1),
            o,
        )
    }

    /// A converged attempt: the scheme's end state (x_{n+1}, v_{n+1}, a_{n+1}) evaluated, so
    /// that outputs, guards and the energy balance see x_{n+1}.
    fn finish_attempt<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        t1: f64,
        iterations: usize,
        hist: Vec<f64>,
    ) -> std::result::Result<(usize, Vec<f64>), Attempt> {
        let o = self.opts(None, t1);
        if let Err(e) = self.scheme.finish(
            &mut self.sys,
            self.model,
            provider,
            (&self.x1, &self.v1, &mut self.a1),
            &o,
        ) {
            return Err(Attempt {
                reason: e.into(),
                history: hist,
            });
        }
        Ok((iterations, hist))
    }

    /// The round-off of a rigid body's inertia residual I·a: its accumulated rotation vector ψ
    /// holds its last step only to ε·|ψ|, which I·a amplifies by the scheme's mass
    /// coefficient `m` (1/(βΔt²), 1/(θΔt²)) [N·m]; 8 roundings, ψ counted from 1 rad
    /// (docs/theory/fem.md#rigid-bodies). Zero without bodies.
    fn body_round_off(&self, m: f64) -> f64 {
        let model = self.model;
        let sq: f64 = model
            .rigid_bodies()
            .iter()
            .map(|b| {
                let i_max = b
                    .inertia
                    .iter()
                    .map(|r| r.iter().map(|c| c.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                let psi = self.state.x[b.rotation_node]
                    .iter()
                    .fold(0.0f64, |a, c| a.max(c.abs()));
                (8.0 * f64::EPSILON * (psi + 1.0) * i_max * m).powi(2)
            })
            .sum();
        sq.sqrt()
    }

    /// F_ref = max(‖f_ext‖₂, ‖R‖₂, ‖M·a‖₂, floor) from the last evaluation.
    fn f_ref(&self) -> f64 {
        let mut fe = 0.0;
        let mut re = 0.0;
        let mut ine = 0.0;
        for i in 0..self.model.n_nodes() {
            for k in 0..3 {
                fe += self.sys.fext[i][k].powi(2);
                ine += self.sys.ma[i][k].powi(2);
                if self.sys.free_of_dof[3 * i + k] == NONE {
                    re += (self.sys.q[i][k] + self.sys.ma[i][k]).powi(2);
                }
            }
        }
        fe.sqrt().max(re.sqrt()).max(ine.sqrt()).max(self.f_floor)
    }
}
