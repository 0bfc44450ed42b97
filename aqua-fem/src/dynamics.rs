//! Implicit dynamics: HHT-α with Newton every step and adaptive step halving
//! (docs/theory/fem.md#hht-alpha, #step-control).

use crate::error::{FemError, Result, invalid};
use crate::line_relaxation::{LineRelaxation, StepKinematics};
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::state::{Outputs, State};
use crate::system::{Coef, EvalOptions, NONE, System};
use serde::{Deserialize, Serialize};

/// Mass matrix of the cable elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum MassMatrix {
    /// μL0/2 on each node (default).
    #[default]
    Lumped,
    /// μL0/6·[2I, I; I, 2I].
    Consistent,
}

/// Settings of the HHT-α integrator (scene keys of `[analysis.dynamic]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicSettings {
    /// α ∈ [0, 1/3] (our convention; α = 0 is the trapezoidal rule). Default 0.3.
    pub alpha: f64,
    /// Nominal (and largest) step Δt [s].
    pub dt: f64,
    /// End time [s].
    pub t_end: f64,
    /// Smallest step before failing [s]; default dt/1024.
    pub dt_min: Option<f64>,
    /// Relative residual tolerance ε_r. Default 1e-5.
    pub tol: f64,
    /// Newton iterations per step. Default 15.
    pub max_iter: usize,
    /// Mass matrix. Default lumped.
    pub mass_matrix: MassMatrix,
    /// Rayleigh damping [a_M (1/s), a_K (s)]: C += a_M·M + a_K·K_material. Default none.
    pub rayleigh: [f64; 2],
    /// Steps are shortened to land on multiples of this interval [s] (flagged in the report).
    pub output_interval: Option<f64>,
    /// Largest |strain| accepted in a step. Default 1.0.
    pub max_strain: f64,
    /// Form missing water-load position derivatives by finite differences. Default false
    /// (the provider's ∂f/∂x is used when given; ∂f/∂v is always formed).
    pub fd_position_jacobian: bool,
    /// Modified Newton (docs/theory/fem.md#hht-alpha): a numeric factorisation serves up to this
    /// many Newton iterations, also across steps of equal Δt, while every iteration with a reused
    /// factorisation reduces ‖r‖ at least 2× (otherwise J is re-formed at the current iterate). 1
    /// (default) = full Newton, a factorisation every iteration.
    #[serde(default = "one")]
    pub reuse_factor: usize,
    /// The energy-consistent implicit midpoint rule instead of HHT-α (α is then unused):
    /// cable forces are the discrete gradient of the strain energy over the step, so an
    /// undamped structure keeps its energy exactly whatever the step
    /// (docs/theory/fem.md#energy-consistent-midpoint). Default false.
    #[serde(default)]
    pub midpoint: bool,
    /// Weight θ ∈ [½, 1] of the end velocity in the midpoint rule's position update,
    /// x_{n+1} − x_n = Δt·((1 − θ)·v_n + θ·v_{n+1}). ½ (default) conserves the energy; θ > ½
    /// removes exactly (θ − ½)·‖v_{n+1} − v_n‖²_M per step from the conservative part of the
    /// energy balance, at first-order accuracy: it damps motion with velocity jumps (the
    /// chatter of slack elements) and a linear mode most at ωΔt = 2/(θ − ½) (spectral radius
    /// 0.60 at ωΔt = 8 for θ = 0.75, ⅓ at 4 for θ = 1), but not the ωΔt → ∞ limit, where one
    /// root tends to −1 (docs/theory/fem.md#energy-decaying-midpoint). Midpoint rule only.
    #[serde(default = "half")]
    pub theta: f64,
    /// How each Newton system is solved (docs/theory/fem.md#sparse-linear-algebra). Default
    /// [`LinearSolverKind::Symmetric`].
    #[serde(default)]
    pub linear_solver: LinearSolverKind,
    /// After each Newton update, solve the interior of every free line with its ends held,
    /// carrying slack-to-taut switches along it within the iteration
    /// (docs/theory/fem.md#line-relaxation). Default true; with HHT-α a step in which a line
    /// tightens across more than `HHT_FRONT_ELEMENTS` elements is halved
    /// (docs/theory/fem.md#line-relaxation-hht).
    #[serde(default = "yes")]
    pub line_relaxation: bool,
}

/// The factorisation of the dynamic Newton systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinearSolverKind {
    /// L·D·Lᵀ of the symmetric part, refined on the non-symmetric rest to 1e-10 of the
    /// right-hand side or to 1 % of the Newton tolerance, with the sparse LU as fallback when
    /// the refinement does not contract.
    #[default]
    Symmetric,
    /// Sparse LU with partial pivoting of the full tangent.
    Lu,
}

/// Counters of the dynamic Newton systems' linear solves.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct LinearSolverStats {
    /// Numeric factorisations (L·D·Lᵀ or LU).
    pub factorisations: usize,
    /// Symmetric solves that kept an earlier L·D·Lᵀ as the preconditioner.
    pub factor_reuses: usize,
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
}

/// A Newton update's linear solve may leave a residual of this fraction of the Newton
/// residual tolerance (inexact Newton; docs/theory/fem.md#sparse-linear-algebra).
const LINEAR_FORCING: f64 = 1e-2;

/// Fraction of the predicted nonlinear remainder that an update's solve may leave while that
/// remainder is above the Newton tolerance (docs/theory/fem.md#sparse-linear-algebra).
const EW_FRACTION: f64 = 0.1;

/// Contraction ‖r_k‖/‖r_{k−1}‖ below which Newton counts as in its quadratic regime, where the
/// forcing term applies.
const EW_REGIME: f64 = 0.1;

/// A landing step within this fraction of Δt of the step itself is taken as Δt (the
/// difference is the round-off of t_out − t).
const LANDING_ROUNDOFF: f64 = 1e-9;

/// Lines are relaxed down to this fraction of the Newton tolerance's force
/// (docs/theory/fem.md#line-relaxation).
const LINE_FLOOR: f64 = 1e-2;

/// HHT-α with line relaxation: a step in which one line's relaxation took more local
/// iterations than this while an element of it that was slack ended taut (a tightening front
/// crossing about as many elements) is halved (docs/theory/fem.md#line-relaxation-hht).
const HHT_FRONT_ELEMENTS: usize = 10;

/// Smallest fraction of a Newton update that backtracking tries.
const MIN_STEP_SCALE: f64 = 1.0 / 16.0;

fn one() -> usize {
    1
}

fn yes() -> bool {
    true
}

fn half() -> f64 {
    0.5
}

impl DynamicSettings {
    /// Defaults with step dt [s] and end time t_end [s].
    pub fn new(dt: f64, t_end: f64) -> Self {
        Self {
            alpha: 0.3,
            dt,
            t_end,
            dt_min: None,
            tol: 1e-5,
            max_iter: 15,
            mass_matrix: MassMatrix::Lumped,
            rayleigh: [0.0, 0.0],
            output_interval: None,
            max_strain: 1.0,
            fd_position_jacobian: false,
            reuse_factor: 1,
            midpoint: false,
            theta: 0.5,
            linear_solver: LinearSolverKind::Symmetric,
            line_relaxation: true,
        }
    }

    /// α from the spectral radius at infinite frequency ρ∞ ∈ [0.5, 1]: α = (1 − ρ∞)/(1 + ρ∞).
    pub fn alpha_from_rho_inf(rho_inf: f64) -> Result<f64> {
        if !(0.5..=1.0).contains(&rho_inf) {
            return Err(invalid(
                "rho_inf",
                rho_inf,
                "0.5 <= rho_inf <= 1 (equivalently alpha in [0, 1/3], or Code_Aster/HHT ALPHA in [-1/3, 0])",
            ));
        }
        Ok((1.0 - rho_inf) / (1.0 + rho_inf))
    }

    /// α from the original HHT / Code_Aster convention α_neg ∈ [−1/3, 0]: α = −α_neg.
    pub fn alpha_from_negative(alpha_neg: f64) -> Result<f64> {
        if !(-1.0 / 3.0 - 1e-15..=0.0).contains(&alpha_neg) {
            return Err(invalid(
                "HHT ALPHA (negative convention)",
                alpha_neg,
                "-1/3 <= ALPHA <= 0 (equivalently alpha in [0, 1/3] or rho_inf in [0.5, 1])",
            ));
        }
        Ok(-alpha_neg)
    }

    fn validate(&self) -> Result<()> {
        if !(0.0..=1.0 / 3.0 + 1e-15).contains(&self.alpha) {
            return Err(invalid(
                "alpha",
                self.alpha,
                "0 <= alpha <= 1/3 (equivalently rho_inf in [0.5, 1], or Code_Aster/HHT ALPHA in [-1/3, 0])",
            ));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(invalid("dt [s]", self.dt, "> 0"));
        }
        if !self.t_end.is_finite() {
            return Err(invalid("t_end [s]", self.t_end, "finite"));
        }
        if let Some(m) = self.dt_min
            && !(m > 0.0 && m <= self.dt)
        {
            return Err(invalid(
                "dt_min [s]",
                m,
                format!("0 < dt_min <= dt = {}", self.dt),
            ));
        }
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return Err(invalid("dynamic tol", self.tol, "0 < tol < 1"));
        }
        if self.max_iter == 0 {
            return Err(invalid("dynamic max_iter", 0.0, ">= 1"));
        }
        if self.reuse_factor == 0 {
            return Err(invalid("reuse_factor", 0.0, ">= 1 (1 = full Newton)"));
        }
        for (i, r) in self.rayleigh.iter().enumerate() {
            if !(r.is_finite() && *r >= 0.0) {
                return Err(invalid(format!("rayleigh[{i}]"), *r, ">= 0"));
            }
        }
        if let Some(o) = self.output_interval
            && !(o.is_finite() && o > 0.0)
        {
            return Err(invalid("output_interval [s]", o, "> 0"));
        }
        if !(self.max_strain > 0.0) {
            return Err(invalid("max_strain", self.max_strain, "> 0"));
        }
        if !(0.5..=1.0).contains(&self.theta) {
            return Err(invalid(
                "theta",
                self.theta,
                "0.5 <= theta <= 1 (0.5 conserves the energy)",
            ));
        }
        if !self.midpoint && self.theta != 0.5 {
            return Err(invalid(
                "theta",
                self.theta,
                "only with the midpoint rule (HHT-alpha damps through alpha or rho_inf)",
            ));
        }
        Ok(())
    }
}

/// Energy balance since the start of the run [J]:
/// W_ext + W_sup = ΔE_k + ΔU + D + E_num.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Energies {
    /// Kinetic energy ½vᵀ(M + M_added)v now.
    pub kinetic: f64,
    /// Strain energy ΣU_e now.
    pub strain: f64,
    /// Work of external forces (gravity, point, water, seabed) since the start.
    pub external_work: f64,
    /// Work of the support reactions since the start.
    pub support_work: f64,
    /// Energy dissipated by axial and Rayleigh damping since the start.
    pub damping_dissipation: f64,
    /// Numerical dissipation E_num (≈ 0 for α = 0).
    pub numerical_dissipation: f64,
}

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

struct Attempt {
    reason: String,
    history: Vec<f64>,
}

/// HHT-α time integrator; advance with [`step`](Self::step) and read results after each step.
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
    /// Midpoint rule: the state the equations are evaluated at.
    xm: Vec<[f64; 3]>,
    vm: Vec<[f64; 3]>,
    am: Vec<[f64; 3]>,
    /// Storage of the step's end positions for the discrete gradient, between evaluations.
    secant_buf: Option<crate::system::StepEnds>,
    /// Positions where the integration started (for the error indicator's scale).
    x_start: Vec<[f64; 3]>,
    /// The balance of the step the guard accepted (its outputs are in `trial`).
    guarded: Option<Balance>,
}

/// Relative energy a step may create before it is rejected (docs/theory/fem.md#step-control):
/// HHT-α (α ≥ 0) only dissipates in linear problems; growth beyond round-off and the
/// trapezoidal work of state-dependent loads means the step left the physics.
/// The step-control reason (a key of [`StepControl::reasons`]) of a step rejected because it
/// created energy (docs/theory/fem.md#step-control).
pub const ENERGY_CREATED: &str = "the step created energy";

pub const ENERGY_GROWTH_TOL: f64 = 0.01;

/// The energy terms of one step (see `DynamicSolver::balance`).
#[derive(Debug, Clone, Copy, Default)]
struct Balance {
    kinetic: f64,
    strain: f64,
    power: f64,
    external_work: f64,
    support_work: f64,
    /// Σ|work| over the DOFs: the scale of the trapezoidal work's own error.
    work_magnitude: f64,
    /// Kinetic energy of the free DOFs.
    kinetic_free: f64,
    /// Work of the supports without the inertia of the supported DOFs (what they pass on to
    /// the rest of the structure, whatever the prescribed velocity does).
    support_work_static: f64,
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
    /// Halvings per reason, in order of first occurrence.
    pub reasons: Vec<(String, usize)>,
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
        let jump = t
            .windows(2)
            .filter(|w| w[0] >= top || w[1] >= top)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        // A sine's slope in its top quarter is at most cos 30° of its slope at the mean.
        let r = jump / (amplitude * 0.75f64.sqrt());
        TensionResolution {
            jump,
            range: [lo, hi],
            error: r * r / 8.0 * amplitude / hi,
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
    /// Why it failed.
    pub reason: String,
}

impl StepControl {
    /// Halvings kept in `events`.
    pub const MAX_EVENTS: usize = 100;

    fn record(&mut self, t: f64, dt: f64, next_dt: f64, reason: &str) {
        self.halvings += 1;
        self.smallest_dt = if self.smallest_dt > 0.0 {
            self.smallest_dt.min(next_dt)
        } else {
            next_dt
        };
        // Group by the kind of reason: the text before any parenthesis, numbers as "…".
        let kind: String = reason
            .split('(')
            .next()
            .unwrap_or(reason)
            .split_whitespace()
            .map(|w| {
                if w.contains(|c: char| c.is_ascii_digit()) {
                    "…"
                } else {
                    w
                }
            })
            .collect::<Vec<_>>()
            .join(" ");
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
            });
        }
    }
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
            if free && model.lumped_mass[i] <= 0.0 {
                return Err(FemError::InvalidModel(format!(
                    "node {i} has free DOFs but no mass (give it an element or a point mass)"
                )));
            }
        }
        let mut a = std::mem::take(&mut state.a);
        model.apply_constraints(state.t, 1.0, &mut state.x, &mut state.v, &mut a);
        state.a = a;
        let max_ea = model.elements().iter().map(|e| e.ea).fold(0.0, f64::max);
        let wsum: f64 = model.weight.iter().map(|w| w[2].abs()).sum();
        let nf = sys.n_free();
        let lines = LineRelaxation::new(model, &sys);
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
            control: StepControl::default(),
            kinetic_free: 0.0,
            xm: vec![[0.0; 3]; n],
            vm: vec![[0.0; 3]; n],
            am: vec![[0.0; 3]; n],
            secant_buf: None,
            x_start: Vec::new(),
            guarded: None,
        };
        // Initial acceleration on free DOFs: M_ff·a_f = −q_f − (M·a_c)_f.
        for (f, &gd) in s.sys.dof_of_free.iter().enumerate() {
            let _ = f;
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
        LinearSolverStats {
            factorisations: self.sys.n_factorisations,
            factor_reuses: self.sys.n_factor_reuses,
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

    /// The energy terms of a step from `x_old` to the last evaluation (`self.sys`, with
    /// `out` its outputs) at (`x_new`, `v_new`); `mv` is scratch (docs/theory/fem.md#hht-alpha).
    fn balance(
        &self,
        x_old: &[[f64; 3]],
        x_new: &[[f64; 3]],
        v_new: &[[f64; 3]],
        out: &Outputs,
        mv: &mut [[f64; 3]],
    ) -> Balance {
        let model = self.model;
        let n = model.n_nodes();
        // Kinetic energy with structural + added mass.
        crate::system::mul_mass(
            model,
            self.st.mass_matrix == MassMatrix::Consistent,
            v_new,
            mv,
        );
        let mut b = Balance {
            // Axial and bending (docs/theory/fem.md#bending) strain energy.
            strain: out.strain_energy(model) + self.sys.bending_energy(),
            ..Balance::default()
        };
        for i in 0..n {
            for k in 0..3 {
                let mut m = mv[i][k];
                for l in 0..3 {
                    m += self.sys.added[i][k][l] * v_new[i][l];
                }
                b.kinetic += 0.5 * v_new[i][k] * m;
                if !model.is_constrained(i, k) {
                    b.kinetic_free += 0.5 * v_new[i][k] * m;
                }
            }
        }
        // Dissipated power: axial/Rayleigh-K damping and Rayleigh-M.
        for (e, c) in model.elements().iter().zip(&self.sys.cable) {
            b.power += c.damping_force * c.strain_rate * e.l0;
        }
        if self.st.rayleigh[0] > 0.0 {
            let mut ms = 0.0;
            for i in 0..n {
                for k in 0..3 {
                    ms += v_new[i][k] * mv[i][k];
                }
            }
            b.power += self.st.rayleigh[0] * ms;
        }
        for i in 0..n {
            for k in 0..3 {
                let dx = x_new[i][k] - x_old[i][k];
                let we = 0.5 * (self.fext_prev[i][k] + self.sys.fext[i][k]) * dx;
                let ws = 0.5 * (self.last_reaction[i][k] + out.reaction[i][k]) * dx;
                b.external_work += we;
                b.support_work += ws;
                b.work_magnitude += we.abs() + ws.abs();
                if model.is_constrained(i, k) {
                    b.support_work_static += 0.5 * (self.q_prev[i][k] + self.sys.q[i][k]) * dx;
                }
            }
        }
        b
    }

    /// Updates outputs and energies from the last evaluation (at the new state).
    fn accept_bookkeeping(&mut self, h: f64, first: bool) {
        let b = match self.guarded.take() {
            // The guard already formed the new state's outputs and balance.
            Some(b) => {
                std::mem::swap(&mut self.outputs, &mut self.trial);
                b
            }
            None => {
                self.outputs.update(self.model, &self.sys, true);
                let mut mv = std::mem::take(&mut self.mv);
                // x1 holds x_n here (swapped in `step`).
                let b = self.balance(
                    &self.x1,
                    &self.state.x,
                    &self.state.v,
                    &self.outputs,
                    &mut mv,
                );
                self.mv = mv;
                b
            }
        };
        let peak = self.outputs.tension.iter().fold(0.0f64, |m, &t| m.max(t));
        self.control.peak_tensions.push(peak);
        if !first {
            self.energies.external_work += b.external_work;
            self.energies.support_work += b.support_work;
            self.energies.damping_dissipation += 0.5 * (self.power_prev + b.power) * h;
        }
        self.energies.kinetic = b.kinetic;
        self.energies.strain = b.strain;
        self.kinetic_free = b.kinetic_free;
        self.energies.numerical_dissipation = self.energies.external_work
            + self.energies.support_work
            - (b.kinetic + b.strain - self.e0)
            - self.energies.damping_dissipation;
        self.power_prev = b.power;
        self.q_prev.copy_from_slice(&self.sys.q);
        self.fext_prev.copy_from_slice(&self.sys.fext);
        self.last_reaction.copy_from_slice(&self.outputs.reaction);
    }

    /// Why a converged attempt (x1, v1 with `self.sys` evaluated there) must still be
    /// rejected (docs/theory/fem.md#step-control): an element that resists compression or was
    /// taut turned over in one step (the true motion would pass through zero length), or the
    /// step created energy: ΔE_k,free + ΔU + D − W_ext − W_sup,q > ENERGY_GROWTH_TOL·E_scale, with
    /// E_scale = max(E_n, E_n+1) + Σ_dofs |W| (the trapezoidal work of loads that balance each
    /// other, e.g. weight and tension, is exact only to O(Δt³) per DOF).
    fn guard(&mut self, h: f64) -> Option<String> {
        let model = self.model;
        self.guarded = None;
        for (e, (el, c)) in model.elements().iter().zip(&self.sys.cable).enumerate() {
            let (a, b) = (el.a, el.b);
            let d0 = crate::system::sub(self.state.x[b], self.state.x[a]);
            let d1 = crate::system::sub(self.x1[b], self.x1[a]);
            let dot = d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2];
            let resisted = el.rc > 0.0 || c.strain > 0.0 || self.outputs.strain[e] > 0.0;
            if dot < 0.0 && resisted {
                return Some(format!(
                    "element {e} turned over in one step (its direction reversed while it carried load)"
                ));
            }
        }
        let mut trial = std::mem::take(&mut self.trial);
        trial.update(model, &self.sys, true);
        let mut mv = std::mem::take(&mut self.mv);
        let b = self.balance(&self.state.x, &self.x1, &self.v1, &trial, &mut mv);
        self.mv = mv;
        self.trial = trial;
        // The balance of the free DOFs: a prescribed node's own kinetic energy is the
        // support's business (a table motion may jump its velocity).
        let e_old = self.kinetic_free + self.energies.strain;
        let e_new = b.kinetic_free + b.strain;
        let created = e_new - e_old + 0.5 * (self.power_prev + b.power) * h
            - b.external_work
            - b.support_work_static;
        let scale = e_old.max(e_new) + b.work_magnitude + self.f_floor * model.mean_length;
        if created > ENERGY_GROWTH_TOL * scale {
            return Some(format!(
                "{ENERGY_CREATED} ({created:.3e} J, {:.1} % of {scale:.3e} J)",
                100.0 * created / scale
            ));
        }
        // Accepted: the bookkeeping reuses these outputs and this balance.
        self.guarded = Some(b);
        None
    }

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
            let outcome = self
                .attempt(provider, h)
                .and_then(|ok| match self.guard(h) {
                    Some(reason) => Err(Attempt {
                        reason,
                        history: ok.1.clone(),
                    }),
                    None => Ok(ok),
                });
            match outcome {
                Ok((iters, hist)) => {
                    if hist.len() >= 2 && hist[0] > 0.0 {
                        self.first_contraction = hist[1] / hist[0];
                    }
                    self.full_newton = false;
                    self.track_time_error(h);
                    self.clamp = false;
                    self.total_iterations += iters;
                    self.n_steps += 1;
                    std::mem::swap(&mut self.state.x, &mut self.x1);
                    std::mem::swap(&mut self.state.v, &mut self.v1);
                    std::mem::swap(&mut self.state.a, &mut self.a1);
                    self.state.t = if landed { target } else { t + h };
                    // x1 now holds x_n (for the work increments).
                    self.accept_bookkeeping(h, false);
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
                    if !self.full_newton && self.attempt_stale_solves > 0 {
                        // Modified Newton failed: retry the same step with full Newton first.
                        self.full_newton = true;
                        continue;
                    }
                    // The clamp changes the tangent only where a slack element pushes: with the
                    // midpoint rule that is rare (tension-only slack elements carry at most
                    // their damping force), and a retry that cannot differ costs max_iter.
                    let clamp_matters = |c: &crate::cable::CableEval| {
                        c.switch < 1.0 && (!self.st.midpoint || c.tension < 0.0)
                    };
                    if !self.clamp && self.sys.cable.iter().any(clamp_matters) {
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

    /// One Newton solve of the HHT-α residual for a step h. On success x1, v1, a1 hold the new
    /// state and `sys` its evaluation.
    fn attempt<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        h: f64,
    ) -> std::result::Result<(usize, Vec<f64>), Attempt> {
        let model = self.model;
        let alpha = self.st.alpha;
        let beta = 0.25 * (1.0 + alpha) * (1.0 + alpha);
        let gamma = 0.5 + alpha;
        let t1 = self.state.t + h;
        let n = model.n_nodes();
        // Predictor.
        for i in 0..n {
            for k in 0..3 {
                let (x, v, a) = (self.state.x[i][k], self.state.v[i][k], self.state.a[i][k]);
                self.x1[i][k] = x + h * v + 0.5 * h * h * a;
            }
        }
        model.apply_constraints(t1, 1.0, &mut self.x1, &mut self.v1, &mut self.a1);
        let midpoint = self.st.midpoint;
        // ∂r/∂x_{n+1} = m·M + k·K + c·C (HHT: Newmark; midpoint: a_m = (v1 − v_n)/h,
        // x_m = (x_n + x1)/2, v_m = (1 − θ)·v_n + θ·v1 with v1 = (x1 − x_n)/(θh) − (1 − θ)/θ·v_n).
        let (coef, t_eval, wq) = if midpoint {
            let c = Coef {
                m: 1.0 / (self.st.theta * h * h),
                k: 0.5,
                c: 1.0 / h,
            };
            (c, self.state.t + 0.5 * h, 1.0)
        } else {
            let c = Coef {
                m: 1.0 / (beta * h * h),
                k: 1.0 - alpha,
                c: (1.0 - alpha) * gamma / (beta * h),
            };
            (c, t1, 1.0 - alpha)
        };
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
        let fail = |reason: String, hist: &Vec<f64>| Attempt {
            reason,
            history: hist.clone(),
        };
        for it in 0..self.st.max_iter {
            if midpoint {
                self.midpoint_kinematics(h);
            } else {
                // Newmark kinematics on free DOFs.
                for &gd in &self.sys.dof_of_free {
                    let (i, k) = (gd / 3, gd % 3);
                    let (xn, vn, an) = (self.state.x[i][k], self.state.v[i][k], self.state.a[i][k]);
                    let a = (self.x1[i][k] - xn - h * vn) / (beta * h * h)
                        - (1.0 / (2.0 * beta) - 1.0) * an;
                    self.a1[i][k] = a;
                    self.v1[i][k] = vn + h * ((1.0 - gamma) * an + gamma * a);
                }
            }
            // Modified Newton: keep the stored factorisation while it is fresh enough; then
            // the Jacobian need not be assembled.
            let mut refactor = !(reuse > 1 && self.lu_valid && self.lu_uses < reuse);
            // When the last update is expected to have converged the step, the evaluation
            // forms no Jacobian: the check that ends the step is the simplified Newton
            // correction with the factor just used (docs/theory/fem.md#convergence-check).
            let lazy = refactor && expect_done && self.lu_valid && self.lu_h == h;
            let oe = if refactor && !lazy { &o } else { &o_res };
            if let Err(e) = self.evaluate_at_step(provider, oe) {
                return Err(fail(e.to_string(), &hist));
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
                return Err(fail("non-finite residual".into(), &hist));
            }
            if it == 0 {
                r0 = rn;
            } else if rn > 1e4 * r0 && rn > self.st.tol * f_ref {
                return Err(fail("residual grew by more than 1e4".into(), &hist));
            }
            let tol = self.st.tol * f_ref;
            if lazy {
                if rn <= tol {
                    refactor = false;
                } else if let Err(e) = self.evaluate_at_step(provider, &o) {
                    return Err(fail(e.to_string(), &hist));
                }
            }
            let max_strain = self.st.max_strain;
            let strain_check = |sys: &System, hist: &Vec<f64>| match sys
                .cable
                .iter()
                .find(|c| c.strain.abs() > max_strain)
            {
                Some(c) => Err(Attempt {
                    reason: format!("strain {:.3e} beyond max_strain {max_strain}", c.strain),
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
                    return Err(fail(e.to_string(), &hist));
                }
            }
            if refactor {
                self.lu_valid = false;
                if let Err(e) = self.sys.factorize() {
                    return Err(fail(e.to_string(), &hist));
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
                Err(e) => return Err(fail(e.to_string(), &hist)),
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
                let kin = StepKinematics {
                    midpoint,
                    h,
                    beta,
                    gamma,
                    xn: &self.state.x,
                    vn: &self.state.v,
                    an: &self.state.a,
                    x_eval: if midpoint { &self.xm } else { &self.x_iter },
                    v_eval: if midpoint { &self.vm } else { &self.v1 },
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
                if !midpoint && self.lines.last_front > HHT_FRONT_ELEMENTS {
                    // The plain Newton iteration would have failed here: for HHT-α that
                    // failure, and the halving it forces, is what resolves the event
                    // (docs/theory/fem.md#line-relaxation-hht).
                    return Err(fail(
                        format!(
                            "a line tightened across more than {HHT_FRONT_ELEMENTS} elements \
                             within the step"
                        ),
                        &hist,
                    ));
                }
            }
        }
        Err(fail(
            format!("no convergence in {} Newton iterations", self.st.max_iter),
            &hist,
        ))
    }

    /// The local error estimate of an accepted step (Zienkiewicz and Xie): the Newmark family's
    /// leading truncation term e = |β − 1/6|·Δt²·‖a_{n+1} − a_n‖_∞ over the free DOFs, with
    /// β = (1 + α)²/4 (β = 1/4 for the midpoint rule), and the largest displacement so far.
    fn track_time_error(&mut self, h: f64) {
        let beta = if self.st.midpoint {
            0.25
        } else {
            0.25 * (1.0 + self.st.alpha).powi(2)
        };
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

    /// Midpoint rule: v1 on the free DOFs from x1, and the midpoint state (x_m, v_m, a_m) on
    /// all DOFs (the constrained ones follow their motion at t_n and t_{n+1}). With the weight θ
    /// (½ for the plain rule): v1 = (x1 − x_n)/(θ·h) − (1 − θ)/θ·v_n and
    /// v_m = (1 − θ)·v_n + θ·v1, which is (x1 − x_n)/h on the free DOFs for every θ; on a
    /// constrained DOF v_m = ½(v_n + v1), its velocity at the midpoint time.
    fn midpoint_kinematics(&mut self, h: f64) {
        let th = self.st.theta;
        let lag = (1.0 - th) / th;
        for &gd in &self.sys.dof_of_free {
            let (i, k) = (gd / 3, gd % 3);
            self.v1[i][k] =
                (self.x1[i][k] - self.state.x[i][k]) / (th * h) - lag * self.state.v[i][k];
        }
        for i in 0..self.model.n_nodes() {
            for k in 0..3 {
                let (x0, v0) = (self.state.x[i][k], self.state.v[i][k]);
                self.xm[i][k] = 0.5 * (x0 + self.x1[i][k]);
                // Free DOFs: (x1 − x_n)/h. A prescribed DOF moves as its motion says, so its
                // velocity at t_n + h/2, where the forces are evaluated, is the mean of its ends
                // whatever θ (docs/theory/fem.md#energy-decaying-midpoint).
                let w = if self.sys.free_of_dof[3 * i + k] == NONE {
                    0.5
                } else {
                    th
                };
                self.vm[i][k] = (1.0 - w) * v0 + w * self.v1[i][k];
                self.am[i][k] = (self.v1[i][k] - v0) / h;
            }
        }
    }

    /// Evaluates the step's equations: at x1 for HHT-α, at the midpoint with discrete-gradient
    /// cable forces between x_n and x1 for the midpoint rule.
    fn evaluate_at_step<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        o: &EvalOptions,
    ) -> Result<()> {
        if !self.st.midpoint {
            return self
                .sys
                .evaluate(self.model, provider, &self.x1, &self.v1, &self.a1, o);
        }
        let mut ends = self.secant_buf.take().unwrap_or_default();
        ends.0.clone_from(&self.state.x);
        ends.1.clone_from(&self.x1);
        self.sys.secant = Some(ends);
        let r = self
            .sys
            .evaluate(self.model, provider, &self.xm, &self.vm, &self.am, o);
        // Later evaluations (outputs, guards) are of states, not of steps.
        self.secant_buf = self.sys.secant.take();
        r
    }

    /// A converged attempt: for the midpoint rule, the end state's acceleration (the
    /// midpoint's, which the next predictor uses) and one evaluation at the end state, so that
    /// outputs, guards and the energy balance see x_{n+1}.
    fn finish_attempt<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        t1: f64,
        iterations: usize,
        hist: Vec<f64>,
    ) -> std::result::Result<(usize, Vec<f64>), Attempt> {
        if self.st.midpoint {
            for &gd in &self.sys.dof_of_free {
                self.a1[gd / 3][gd % 3] = self.am[gd / 3][gd % 3];
            }
            let o = self.opts(None, t1);
            if let Err(e) = self
                .sys
                .evaluate(self.model, provider, &self.x1, &self.v1, &self.a1, &o)
            {
                return Err(Attempt {
                    reason: e.to_string(),
                    history: hist,
                });
            }
        }
        Ok((iterations, hist))
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
        }))
    }
}
