//! Settings of the implicit integrators (scene keys of `[analysis.dynamic]`) and their
//! validation.

use crate::error::{Result, invalid};
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

/// Settings of the implicit integrators, HHT-α or the midpoint rule (scene keys of `[analysis.dynamic]`).
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
    #[serde(default = "default_theta")]
    pub theta: f64,
    /// How each Newton system is solved (docs/theory/fem.md#sparse-linear-algebra). Default
    /// [`LinearSolverKind::Symmetric`].
    #[serde(default)]
    pub linear_solver: LinearSolverKind,
    /// After each Newton update, solve the interior of every free line with its ends held,
    /// carrying slack-to-taut switches along it within the iteration
    /// (docs/theory/fem.md#line-relaxation). Default true; with HHT-α a step in which a line
    /// tightens across more than `HHT_FRONT_ELEMENTS` (`hht.rs`) elements is halved
    /// (docs/theory/fem.md#line-relaxation-hht).
    #[serde(default = "yes")]
    pub line_relaxation: bool,
    /// Relative tolerance on each element group's largest tension: a step that samples the
    /// crest of a group's peak tension too coarsely for it is halved, down to `dt_min`
    /// (docs/theory/fem.md#extremes-to-a-tolerance). Default none (no such control).
    #[serde(default)]
    pub extreme_tolerance: Option<f64>,
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

fn one() -> usize {
    1
}

fn yes() -> bool {
    true
}

/// Default HHT α (our convention, α ∈ [0, 1/3]; ρ∞ = (1 − α)/(1 + α) ≈ 0.54).
pub const DEFAULT_ALPHA: f64 = 0.3;
/// Default weight θ of the midpoint rule: ½, the energy-conserving rule.
pub const DEFAULT_THETA: f64 = 0.5;

fn default_theta() -> f64 {
    DEFAULT_THETA
}

impl DynamicSettings {
    /// Defaults with step dt [s] and end time t_end [s].
    pub fn new(dt: f64, t_end: f64) -> Self {
        Self {
            alpha: DEFAULT_ALPHA,
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
            theta: DEFAULT_THETA,
            linear_solver: LinearSolverKind::Symmetric,
            line_relaxation: true,
            extreme_tolerance: None,
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

    pub(super) fn validate(&self) -> Result<()> {
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
        if let Some(e) = self.extreme_tolerance
            && !(e > 0.0 && e < 0.5)
        {
            return Err(invalid(
                "extreme_tolerance",
                e,
                "0 < extreme_tolerance < 0.5 (a relative error, e.g. 0.01)",
            ));
        }
        if !(0.5..=1.0).contains(&self.theta) {
            return Err(invalid(
                "theta",
                self.theta,
                "0.5 <= theta <= 1 (0.5 conserves the energy)",
            ));
        }
        if !self.midpoint && self.theta != DEFAULT_THETA {
            return Err(invalid(
                "theta",
                self.theta,
                "only with the midpoint rule (HHT-alpha damps through alpha or rho_inf)",
            ));
        }
        Ok(())
    }
}
