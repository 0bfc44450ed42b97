//! The schema of `[analysis]`: the kind of run, `[analysis.static]` (aqua-fem's
//! `StaticSettings`, read directly) and `[analysis.dynamic]` (the integrator and its keys).

use aqua_fem::{DynamicSettings, ExplicitScheme, ExplicitSettings, MassMatrix, StaticSettings};
use serde::{Deserialize, Serialize};

/// `analysis.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AnalysisKind {
    /// Static equilibrium only.
    #[serde(rename = "static")]
    Static,
    /// Dynamics only (from the as-built state at rest).
    #[serde(rename = "dynamic")]
    Dynamic,
    /// Static equilibrium, then dynamics from it.
    #[default]
    #[serde(rename = "static+dynamic")]
    StaticDynamic,
}

/// `[analysis.static]` (docs/theory/fem.md#static-solver): the keys are fields of aqua-fem's
/// [`StaticSettings`], whose `Default` gives every default; this adapter only says which fields are
/// scene keys.
#[derive(Deserialize, Serialize)]
#[serde(
    remote = "StaticSettings",
    default = "StaticSettings::default",
    deny_unknown_fields
)]
struct StaticKeys {
    tol: f64,
    max_iter: usize,
    load_steps: usize,
    min_load_step: f64,
    stabilisation: f64,
    line_search: bool,
    watchdog: bool,
    stretch_damping: bool,
    mesh_sequence: usize,
    #[serde(skip)]
    time: f64,
    #[serde(skip)]
    fd_position_jacobian: bool,
}

/// `analysis.dynamic.mass_matrix`: aqua-fem's [`MassMatrix`] with snake_case scene names.
#[derive(Deserialize, Serialize)]
#[serde(remote = "MassMatrix", rename_all = "snake_case")]
enum MassMatrixKey {
    Lumped,
    Consistent,
}

/// `analysis.dynamic.scheme`: the implicit HHT-α integrator or one of aqua-fem's
/// [`ExplicitScheme`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// Implicit HHT-α.
    #[default]
    Hht,
    /// Implicit midpoint with energy-consistent cable forces (aqua-fem's
    /// `DynamicSettings::midpoint`).
    Midpoint,
    /// Explicit lumped mass-spring, symplectic Euler.
    SemiImplicitEuler,
    /// Explicit lumped mass-spring, RK4.
    Rk4,
}

impl Scheme {
    /// The explicit scheme, or `None` for HHT-α.
    pub fn explicit(self) -> Option<ExplicitScheme> {
        match self {
            Scheme::Hht | Scheme::Midpoint => None,
            Scheme::SemiImplicitEuler => Some(ExplicitScheme::SemiImplicitEuler),
            Scheme::Rk4 => Some(ExplicitScheme::Rk4),
        }
    }
}

/// `[analysis.dynamic]` (docs/theory/fem.md#hht-alpha, #step-control, #explicit-schemes): the keys
/// of aqua-fem's [`DynamicSettings`] (HHT-α) and [`ExplicitSettings`]; defaults not given here are
/// theirs ([`DynamicSpec::default`]). Resolved into solver settings by [`crate::plan::Plan`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DynamicSpec {
    /// Integrator.
    pub scheme: Scheme,
    /// HHT α ∈ [0, 1/3] (default 0.3); exclusive with rho_inf.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// Spectral radius at infinity ρ∞ ∈ [0.5, 1]; exclusive with alpha.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    /// Midpoint rule only: weight θ ∈ [0.5, 1] of the end velocity (default 0.5, energy
    /// conserving; above, energy decaying at first order, docs/theory/fem.md#energy-decaying-midpoint).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    /// Time step [s] (HHT: nominal, default [`DEFAULT_DT`]; explicit: upper bound, default
    /// the stable estimate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// End time [s].
    pub t_end: f64,
    /// Smallest step before the run stops [s] (default dt/1024).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_min: Option<f64>,
    /// Explicit: error instead of reducing a user dt above the stable step.
    pub dt_fixed: bool,
    /// Newton tolerance (relative force residual).
    pub tol: f64,
    /// Newton iterations per step.
    pub max_iter: usize,
    /// Lumped or consistent mass.
    #[serde(with = "MassMatrixKey")]
    pub mass_matrix: MassMatrix,
    /// Rayleigh damping [a_M, a_K].
    pub rayleigh: [f64; 2],
    /// Explicit stability factor.
    pub cfl: f64,
    /// Output interval [s] (default max(dt, t_end/200); at least every step).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output_interval: Option<f64>,
    /// Interval of the ParaView series [s] (default: the output interval): a whole multiple of
    /// the output interval, so that a large model writes its `.vtm`/`.vtu` files less often
    /// than its `summary.csv` rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paraview_interval: Option<f64>,
    /// Largest strain before a step is rejected.
    pub max_strain: f64,
    /// Modified Newton: reuse one LU factorisation for up to this many iterations while each
    /// halves the residual (1 = full Newton).
    pub reuse_factor: usize,
    /// Newton systems: `"symmetric"` (default: L·D·Lᵀ of the symmetric part, refined on the
    /// rest, LU fallback) or `"lu"` (docs/theory/fem.md#sparse-linear-algebra).
    pub linear_solver: aqua_fem::LinearSolverKind,
    /// Relax the free lines inside each Newton iteration (docs/theory/fem.md#line-relaxation).
    pub line_relaxation: bool,
    /// Implicit schemes: relative tolerance on each element group's largest tension; steps
    /// that sample a tension crest too coarsely for it are halved, down to `dt_min`
    /// (docs/theory/fem.md#extremes-to-a-tolerance). Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extreme_tolerance: Option<f64>,
}

/// The nominal HHT step when the scene gives none [s].
pub const DEFAULT_DT: f64 = 0.1;
/// The end time when the scene gives none [s].
pub const DEFAULT_T_END: f64 = 10.0;

impl Default for DynamicSpec {
    /// aqua-fem's defaults, with the scene's end time.
    fn default() -> Self {
        let hht = DynamicSettings::new(DEFAULT_DT, DEFAULT_T_END);
        let explicit = ExplicitSettings::new(DEFAULT_T_END);
        Self {
            scheme: Scheme::Hht,
            alpha: None,
            rho_inf: None,
            theta: None,
            dt: None,
            t_end: DEFAULT_T_END,
            dt_min: hht.dt_min,
            dt_fixed: explicit.dt_fixed,
            tol: hht.tol,
            max_iter: hht.max_iter,
            mass_matrix: hht.mass_matrix,
            rayleigh: hht.rayleigh,
            cfl: explicit.cfl,
            output_interval: None,
            paraview_interval: None,
            max_strain: hht.max_strain,
            reuse_factor: hht.reuse_factor,
            linear_solver: hht.linear_solver,
            line_relaxation: hht.line_relaxation,
            extreme_tolerance: hht.extreme_tolerance,
        }
    }
}

/// `[analysis]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// What to compute.
    #[serde(default)]
    pub kind: AnalysisKind,
    /// Statics settings (aqua-fem's, read directly).
    #[serde(default, rename = "static", with = "StaticKeys")]
    pub statics: StaticSettings,
    /// Dynamics settings.
    #[serde(default)]
    pub dynamic: DynamicSpec,
}
