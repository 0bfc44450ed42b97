//! Implicit dynamics (docs/theory/fem.md#hht-alpha, #energy-consistent-midpoint,
//! #step-control): the solver and its state here; one file per job beside it — the settings
//! (`settings.rs`), the step control (`step_control.rs`), the energy ledger (`energy.rs`), the
//! Newton loop every implicit scheme uses (`newton.rs`) and one file per time scheme
//! (`hht.rs`, `midpoint.rs`) behind the dispatch of `scheme.rs`; a saved state for a
//! coupling's save and restore (`snapshot.rs`).

mod contact_resolution;
mod energy;
mod extreme_control;
mod hht;
mod midpoint;
mod newton;
mod scheme;
mod settings;
mod snap_resolution;
mod snapshot;
mod step_control;
mod step_ripple;

pub use contact_resolution::{CONTACT_IMPACT, CONTACT_LOSS_WARNING, ContactResolution};
pub use energy::{ENERGY_GROWTH_TOL, Energies};
pub use extreme_control::ExtremeResolution;
pub(crate) use hht::{HhtForces, use_hht_force};
pub(crate) use scheme::{ForceEvaluation, Scheme};
pub use settings::{DEFAULT_ALPHA, DEFAULT_THETA, DynamicSettings, LinearSolverKind, MassMatrix};
pub use snap_resolution::{
    GroupSnaps, RESOLVED_PHASE, SNAP_EXCESS_WARNING, SnapExtreme, SnapResolution,
};
pub use snapshot::Snapshot;
pub use step_control::{StepControl, StepEvent, StepReport, TensionResolution};
pub use step_ripple::{MIN_RIPPLE_WINDOWS, StepRipple, step_ripple};

use crate::error::{FemError, Result, invalid};
use crate::line_relaxation::LineRelaxation;
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::state::{Outputs, State};
use crate::system::{Coef, EvalOptions, System};
use energy::Balance;
use serde::Serialize;

/// Counters of the dynamic Newton systems' linear solves.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct LinearSolverStats {
    /// Numeric factorisations (L·D·Lᵀ or LU).
    pub factorisations: usize,
    /// Symmetric solves that kept an earlier L·D·Lᵀ as the preconditioner.
    pub factor_reuses: usize,
    /// Solves with a kept L·D·Lᵀ that did not contract, so that the factor was replaced
    /// (each is counted in `factorisations`, not in `factor_reuses`).
    pub stale_failures: usize,
    /// Symmetric solves that fell back to the LU.
    pub fallbacks: usize,
    /// Symmetric solves whose sweeps stalled and that GMRES finished
    /// (docs/theory/fem.md#sparse-linear-algebra).
    pub gmres_rescues: usize,
    /// Refinement sweeps of all symmetric solves (GMRES steps included).
    pub refinement_sweeps: usize,
    /// Free lines that the midpoint rule relaxes (docs/theory/fem.md#line-relaxation).
    pub relaxed_lines: usize,
    /// Local line solves kept.
    pub line_solves_kept: usize,
    /// Local line solves left at the Newton update (their remainder did not fall).
    pub line_solves_reverted: usize,
    /// Block-tridiagonal local Newton iterations over all line solves.
    pub line_iterations: usize,
    /// Convergence checks solved with the last factor and its J, without forming a new J
    /// (simplified Newton corrections; docs/theory/fem.md#convergence-check).
    pub stale_checks: usize,
    /// Parts of the block solve that applies the L·D·Lᵀ part by part, the cages of a farm
    /// factorised in parallel (0: one L·D·Lᵀ of the whole; docs/theory/fem.md#block-solve).
    pub block_parts: usize,
    /// Interface DOFs of that block solve.
    pub block_interface: usize,
}

/// Implicit time integrator (HHT-α or the midpoint rule); advance with [`step`](Self::step)
/// and read results after each step.
#[derive(Debug)]
pub struct DynamicSolver<'m> {
    model: &'m Model,
    st: DynamicSettings,
    sys: System,
    state: State,
    x1: Vec<[f64; 3]>,
    v1: Vec<[f64; 3]>,
    a1: Vec<[f64; 3]>,
    q_prev: Vec<[f64; 3]>,
    fext_prev: Vec<[f64; 3]>,
    power_prev: f64,
    outputs: Outputs,
    r: Vec<f64>,
    dx: Vec<f64>,
    dt_cur: f64,
    good_steps: usize,
    /// The free lines and their relaxation (docs/theory/fem.md#line-relaxation).
    lines: LineRelaxation,
    /// Relax the lines after each Newton update.
    relax_lines: bool,
    /// The Newton iterate before the last update.
    x_iter: Vec<[f64; 3]>,
    energies: Energies,
    e0: f64,
    f_floor: f64,
    n_steps: usize,
    total_iterations: usize,
    last_reaction: Vec<[f64; 3]>,
    clamp: bool,
    mv: Vec<[f64; 3]>,
    /// The stored numeric factorisation is of the HHT Jacobian for a step of `lu_h`.
    lu_valid: bool,
    lu_h: f64,
    /// Newton iterations the stored factorisation has served.
    lu_uses: usize,
    /// Numeric factorisations of the current attempt.
    attempt_factorisations: usize,
    /// Iterations of the current attempt that used a factorisation formed before them
    /// (modified Newton).
    attempt_stale_solves: usize,
    /// Convergence checks with the last factor over the run.
    stale_checks: usize,
    /// ‖r₁‖/‖r₀‖ of the last accepted step (NaN before one): predicts the first update's
    /// nonlinear remainder for the inexact solve.
    first_contraction: f64,
    /// The next attempt uses full Newton: set after a modified-Newton attempt failed, so a
    /// step is halved only when full Newton fails too.
    full_newton: bool,
    /// Outputs of a converged attempt, for its guard.
    trial: Outputs,
    /// Halvings and regrowths so far.
    control: StepControl,
    /// Kinetic energy of the free DOFs at the current state.
    kinetic_free: f64,
    /// The time scheme: its kinematics, Jacobian coefficients and residual weight.
    scheme: Scheme,
    /// Positions where the integration started (for the error indicator's scale).
    x_start: Vec<[f64; 3]>,
    /// The balance of the step the guard accepted (its outputs are in `trial`).
    guarded: Option<Balance>,
    /// Extremes to a tolerance, when `extreme_tolerance` is set.
    extremes: Option<extreme_control::ExtremeControl>,
    /// The seabed contact's landings and lift-offs (None without a seabed the nodes can touch;
    /// docs/theory/fem.md#seabed-contact-resolution).
    contact: Option<contact_resolution::ContactTracker>,
    /// The slack elements' snaps within single steps (None without cable elements;
    /// docs/theory/fem.md#snap-resolution).
    snaps: Option<snap_resolution::SnapTracker>,
}

impl<'m> DynamicSolver<'m> {
    /// Prepares the integrator from `initial` (e.g. a static solution's state) or, if `None`,
    /// from the as-built geometry at rest at t = 0. Computes a₀ from M·a₀ = −q(x₀, v₀, t₀).
    pub fn new<P: LoadProvider + ?Sized>(
        model: &'m Model,
        settings: DynamicSettings,
        initial: Option<&State>,
        provider: &mut P,
    ) -> Result<Self> {
        settings.validate()?;
        let mut sys = System::new(model, &*provider)?;
        sys.symmetric = settings.linear_solver == LinearSolverKind::Symmetric;
        let n = model.n_nodes();
        let mut state = match initial {
            Some(s) => {
                if s.x.len() != n || s.v.len() != n || s.a.len() != n {
                    return Err(FemError::InvalidModel(format!(
                        "initial state has {} nodes, the model {n}",
                        s.x.len()
                    )));
                }
                if s.x.iter().chain(&s.v).flatten().any(|c| !c.is_finite()) || !s.t.is_finite() {
                    return Err(FemError::NonFinite("initial state".into()));
                }
                s.clone()
            }
            None => State::as_built(model, 0.0),
        };
        if settings.t_end < state.t {
            return Err(invalid(
                "t_end [s]",
                settings.t_end,
                format!(">= start time {}", state.t),
            ));
        }
        for i in 0..n {
            let free = (0..3).any(|k| !model.is_constrained(i, k));
            // A rotation carrier's inertia is its body's full block.
            if free && model.lumped_mass[i] <= 0.0 && !model.is_rotation_carrier(i) {
                return Err(FemError::InvalidModel(format!(
                    "node {i} has free DOFs but no mass (give it an element or a point mass)"
                )));
            }
        }
        // The bodies' reference frames start at the initial state's orientations, taken
        // about the as-built axes (a static solution's acceptance,
        // docs/theory/fem.md#rigid-bodies).
        sys.accept_body_frames(model, &state.x);
        let mut a = std::mem::take(&mut state.a);
        model.apply_constraints(state.t, 1.0, &mut state.x, &mut state.v, &mut a);
        state.a = a;
        let max_ea = model.max_axial_stiffness();
        let wsum: f64 = model.weight.iter().map(|w| w[2].abs()).sum();
        let nf = sys.n_free();
        let lines = LineRelaxation::new(model, &sys);
        let settings_scheme = settings.clone();
        let contact = contact_resolution::ContactTracker::new(model);
        let mut s = Self {
            model,
            lines,
            relax_lines: settings.line_relaxation,
            x_iter: Vec::new(),
            dt_cur: settings.dt,
            st: settings,
            sys,
            x1: state.x.clone(),
            v1: state.v.clone(),
            a1: state.a.clone(),
            state,
            q_prev: vec![[0.0; 3]; n],
            fext_prev: vec![[0.0; 3]; n],
            power_prev: 0.0,
            outputs: Outputs::new(model),
            r: vec![0.0; nf],
            dx: vec![0.0; nf],
            good_steps: 0,
            energies: Energies::default(),
            e0: 0.0,
            f_floor: (1e-6 * wsum).max(1e-9 * max_ea).max(1e-12),
            n_steps: 0,
            total_iterations: 0,
            last_reaction: vec![[0.0; 3]; n],
            clamp: false,
            mv: vec![[0.0; 3]; n],
            lu_valid: false,
            lu_h: 0.0,
            lu_uses: 0,
            attempt_factorisations: 0,
            attempt_stale_solves: 0,
            stale_checks: 0,
            first_contraction: f64::NAN,
            full_newton: false,
            trial: Outputs::new(model),
            control: StepControl {
                extremes: settings_scheme
                    .extreme_tolerance
                    .map(|tolerance| ExtremeResolution {
                        tolerance,
                        ..Default::default()
                    }),
                seabed_contact: contact.as_ref().map(|_| ContactResolution::default()),
                ..StepControl::default()
            },
            kinetic_free: 0.0,
            scheme: Scheme::new(&settings_scheme, n),
            x_start: Vec::new(),
            guarded: None,
            extremes: settings_scheme
                .extreme_tolerance
                .map(|tol| extreme_control::ExtremeControl::new(model, tol)),
            contact,
            snaps: snap_resolution::SnapTracker::new(model),
        };
        // Initial acceleration on free DOFs: M_ff·a_f = −q_f − (M·a_c)_f.
        for &gd in &s.sys.dof_of_free {
            s.state.a[gd / 3][gd % 3] = 0.0;
        }
        let o = s.opts(
            Some(Coef {
                m: 1.0,
                k: 0.0,
                c: 0.0,
            }),
            s.state.t,
        );
        s.sys
            .evaluate(model, provider, &s.state.x, &s.state.v, &s.state.a, &o)?;
        for (f, &gd) in s.sys.dof_of_free.iter().enumerate() {
            s.dx[f] = -s.sys.q[gd / 3][gd % 3] - s.sys.ma[gd / 3][gd % 3];
        }
        s.sys.factorize()?;
        s.sys.solve(&mut s.dx)?;
        // The mass matrix alone is no preconditioner for a step's tangent.
        s.sys.require_fresh_factor();
        for (f, &gd) in s.sys.dof_of_free.iter().enumerate() {
            s.state.a[gd / 3][gd % 3] = s.dx[f];
        }
        let o = s.opts(None, s.state.t);
        s.sys
            .evaluate(model, provider, &s.state.x, &s.state.v, &s.state.a, &o)?;
        s.accept_bookkeeping(0.0, true);
        if let Some(c) = s.extremes.as_mut() {
            c.accept(model, &s.outputs.tension, &s.state.x, &s.state.v);
        }
        if let Some(snaps) = s.snaps.as_mut() {
            snaps.observe(&s.outputs.tension);
        }
        s.e0 = s.energies.kinetic + s.energies.strain;
        s.x_start = s.state.x.clone();
        Ok(s)
    }

    fn opts(&self, jacobian: Option<Coef>, t: f64) -> EvalOptions {
        EvalOptions {
            t,
            load_scale: 1.0,
            dynamic: true,
            jacobian,
            inertia: true,
            consistent_mass: self.st.mass_matrix == MassMatrix::Consistent,
            rayleigh: (self.st.rayleigh[0], self.st.rayleigh[1]),
            fd_dfdx: self.st.fd_position_jacobian,
            clamp_geometric: self.clamp,
        }
    }

    /// Current state (after the last accepted step).
    pub fn state(&self) -> &State {
        &self.state
    }
    /// The pose and velocity of every rigid body in the current state, in the order of
    /// [`Model::rigid_bodies`] (docs/theory/fem.md#rigid-bodies).
    pub fn body_poses(&self) -> Vec<crate::rigid_body::BodyPose> {
        self.sys
            .body_poses(self.model, &self.state.x, &self.state.v)
    }
    /// Element tensions, strains, reactions, seabed and water forces of the current state.
    pub fn outputs(&self) -> &Outputs {
        &self.outputs
    }
    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.state.t
    }
    /// Whether t_end has been reached.
    pub fn is_finished(&self) -> bool {
        self.state.t >= self.st.t_end - 1e-9 * self.st.dt
    }
    /// Moves the end time to `t_end` [s], not before the current time: a coupling advances
    /// the solver call by call, each call landing on its own end with the solver's own step
    /// (docs/theory/fem.md#coupling). After a failed step (Δt below `dt_min`) the step starts
    /// again from the nominal dt, so a call can be retried.
    pub fn extend_to(&mut self, t_end: f64) -> Result<()> {
        if !(t_end.is_finite() && t_end >= self.state.t) {
            return Err(invalid(
                "t_end [s]",
                t_end,
                format!("finite and not before the current time {} s", self.state.t),
            ));
        }
        self.st.t_end = t_end;
        if self.dt_cur < self.st.dt_min.unwrap_or(self.st.dt / 1024.0) {
            self.dt_cur = self.st.dt;
            self.good_steps = 0;
        }
        Ok(())
    }
    /// Accepted steps so far.
    pub fn n_steps(&self) -> usize {
        self.n_steps
    }
    /// Newton iterations (factorisations) of accepted steps so far.
    pub fn total_iterations(&self) -> usize {
        self.total_iterations
    }
    /// What the linear solver did so far (docs/theory/fem.md#sparse-linear-algebra).
    pub fn linear_solver_stats(&self) -> LinearSolverStats {
        let block = self
            .sys
            .sym
            .as_ref()
            .and_then(|s| s.block_shape())
            .unwrap_or((0, 0));
        LinearSolverStats {
            factorisations: self.sys.n_factorisations,
            factor_reuses: self.sys.n_factor_reuses,
            stale_failures: self.sys.n_stale_failures,
            fallbacks: self.sys.n_symmetric_fallbacks,
            gmres_rescues: self.sys.sym.as_ref().map_or(0, |s| s.gmres_rescues),
            refinement_sweeps: self.sys.n_refinement_sweeps,
            relaxed_lines: if self.relax_lines {
                self.lines.n_lines()
            } else {
                0
            },
            line_solves_kept: self.lines.kept,
            line_solves_reverted: self.lines.reverted,
            line_iterations: self.lines.local_iterations,
            stale_checks: self.stale_checks,
            block_parts: block.0,
            block_interface: block.1,
        }
    }
    /// What the step control did so far.
    pub fn step_control(&self) -> &StepControl {
        &self.control
    }
    /// Energy balance of the current state.
    pub fn energies(&self) -> Energies {
        self.energies
    }
    /// Diagnostics for benchmarks: numeric LU of the last assembled Jacobian plus one solve,
    /// without assembly (the bare linear-algebra cost of one Newton iteration).
    pub fn factorize_and_solve_last(&mut self) -> Result<()> {
        self.sys.require_fresh_factor();
        self.sys.factorize()?;
        self.dx.copy_from_slice(&self.r);
        self.sys.solve(&mut self.dx)
    }

    /// Number of free DOFs (unknowns).
    pub fn n_free_dofs(&self) -> usize {
        self.sys.n_free()
    }

    /// Settings.
    pub fn settings(&self) -> &DynamicSettings {
        &self.st
    }

    /// Runs to t_end, calling `on_step` after every accepted step; stops early (Ok) when the
    /// callback returns false.
    pub fn run<P: LoadProvider + ?Sized, F: FnMut(&Self, &StepReport) -> bool>(
        &mut self,
        provider: &mut P,
        mut on_step: F,
    ) -> Result<()> {
        while !self.is_finished() {
            let rep = self.step(provider)?;
            if !on_step(self, &rep) {
                break;
            }
        }
        Ok(())
    }
}
