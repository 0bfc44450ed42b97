//! The global system of the free DOFs: what an evaluation leaves (forces, the Jacobian's
//! values, per-element results) and the options it takes. Its jobs are one file each: DOF
//! numbering and the sparse pattern built once (`dofs.rs`), evaluation and assembly of
//! residual and Jacobian (`assembly.rs`), the water-load elements with their finite-difference
//! derivatives (`load_derivatives.rs`) and the linear solver, L·D·Lᵀ or LU with its fallback
//! (`linear_solver.rs`; docs/theory/fem.md#sparse-linear-algebra). The seabed's contact law
//! is `seabed.rs`, its friction `friction.rs`.

mod assembly;
mod bodies;
mod dofs;
mod linear_solver;
mod load_derivatives;
mod net_triangles;
mod rods;
pub(crate) mod schur;

use crate::bending::HingeEval;
use crate::cable::CableEval;
use crate::loads::{ElementLoad, MAX_LOAD_NODES};
use crate::net_triangle::NetTriangleEval;
use crate::rigid_body::{BodyFrame, LinkEval};
use crate::rod::{EdgeFrame, ROD_DOFS, RodEval};
use crate::symmetric::SymmetricSolver;
pub(crate) use assembly::mul_mass;
pub(crate) use bodies::body_poses_with;
use linear_solver::LinearSolver;
use schur::SchurSolver;

pub(crate) const NONE: usize = usize::MAX;

/// Jacobian coefficients: J = m·M + k·K + c·C with K = ∂q/∂x, C = ∂q/∂v.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Coef {
    pub m: f64,
    pub k: f64,
    pub c: f64,
}

/// What to evaluate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EvalOptions {
    pub t: f64,
    /// Scale of gravity, point forces and water loads (load continuation).
    pub load_scale: f64,
    /// Velocity-dependent terms (axial, seabed and Rayleigh damping) active.
    pub dynamic: bool,
    pub jacobian: Option<Coef>,
    /// Compute M·a into `ma`.
    pub inertia: bool,
    pub consistent_mass: bool,
    /// Rayleigh damping (a_M, a_K).
    pub rayleigh: (f64, f64),
    /// Form a missing ∂f_h/∂x by finite differences (otherwise it is omitted).
    pub fd_dfdx: bool,
    /// Use max(T, 0) in the geometric stiffness (robust tangent for slack-dominated states).
    pub clamp_geometric: bool,
}

/// The positions at the start and end of a step.
pub(crate) type StepEnds = (Vec<[f64; 3]>, Vec<[f64; 3]>);

#[derive(Debug)]
pub(crate) struct System {
    pub n_nodes: usize,
    /// Free index of global DOF 3i+k, or NONE.
    pub free_of_dof: Vec<usize>,
    /// Global DOF of each free index.
    pub dof_of_free: Vec<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    pub values: Vec<f64>,
    /// Positions in `values` of each cable element's 6 × 6 block (NONE where a DOF is held).
    pub(crate) cable_pos: Vec<[usize; 36]>,
    hinge_pos: Vec<[usize; 81]>,
    rod_pos: Vec<[usize; ROD_DOFS * ROD_DOFS]>,
    net_pos: Vec<[usize; 81]>,
    node_pos: Vec<[usize; 9]>,
    load_nodes: Vec<[usize; MAX_LOAD_NODES]>,
    load_nn: Vec<usize>,
    load_pos_off: Vec<usize>,
    load_pos: Vec<usize>,
    load_stride: usize,
    load_buf: Vec<f64>,
    /// Per-element results of the last evaluation.
    pub cable: Vec<CableEval>,
    /// Per-hinge results of the last evaluation (energy, force, tangent when a Jacobian was
    /// asked for).
    pub hinge: Vec<HingeEval>,
    /// Per-rod-vertex results of the last evaluation (docs/theory/fem.md#rod).
    pub(crate) rod: Vec<RodEval>,
    /// Per-net-triangle results of the last evaluation (docs/theory/fem.md#net-triangle).
    pub(crate) net: Vec<NetTriangleEval>,
    /// Reference frame of each rod edge: its frame at the last accepted state (as built until
    /// a dynamic step is accepted).
    pub(crate) rod_frames: Vec<EdgeFrame>,
    /// Per rigid link: the positions of its 9×9 block (point, centre, carrier) in `values`.
    link_pos: Vec<[usize; 81]>,
    /// Per-rigid-link results of the last evaluation (docs/theory/fem.md#rigid-bodies).
    pub(crate) link: Vec<LinkEval>,
    /// Reference frame of each rigid body: its orientation and carrier value at the last
    /// accepted state (as built, R = I and ψ = 0, until a solver accepts one).
    body_frames: Vec<BodyFrame>,
    /// Per rigid body: ∂(ω×(I_w·ω))/∂ω of the last dynamic evaluation [kg·m²/s].
    gyro_c: Vec<[[f64; 3]; 3]>,
    /// Internal (elastic + axial damping + Rayleigh) force, q sense [N].
    pub fint: Vec<[f64; 3]>,
    /// External forces on the structure: gravity, point forces, water loads, seabed [N].
    pub fext: Vec<[f64; 3]>,
    /// Water loads from the provider [N].
    pub fhydro: Vec<[f64; 3]>,
    /// Seabed contact force [N].
    pub fbed: Vec<[f64; 3]>,
    /// −∂f_bed,z/∂z of the last evaluation (2·∂/∂z1 for the midpoint rule) [N/m].
    bed_kz: Vec<f64>,
    /// −∂f_bed,z/∂v_z of the last evaluation [N·s/m].
    bed_cz: Vec<f64>,
    /// Cable elements at each node for the friction's line direction: up to two, `NONE`
    /// padded; `None` for a junction of three or more (docs/theory/fem.md#seabed-friction).
    node_lines: Vec<Option<[usize; 2]>>,
    /// Seabed friction of the last evaluation: −∂f/∂x and −∂f/∂v per node (rows x, y).
    fric_k: Vec<[[f64; 3]; 3]>,
    fric_c: Vec<[[f64; 3]; 3]>,
    /// Friction damping μN/v_c outside the linear zone per node (explicit stable step) [N·s/m].
    fric_spare: Vec<f64>,
    /// Friction acted in the last evaluation.
    friction_on: bool,
    /// q = f_int − f_ext [N].
    pub q: Vec<[f64; 3]>,
    /// M·a (structural + added mass) [N].
    pub ma: Vec<[f64; 3]>,
    mv: Vec<[f64; 3]>,
    /// Added-mass blocks per node [kg].
    pub added: Vec<[[f64; 3]; 3]>,
    /// Position of the diagonal entry of each free DOF in `values`.
    pub diag_pos: Vec<usize>,
    solver: Option<LinearSolver>,
    /// Part of each free DOF when the model is partitioned (docs/theory/fem.md#block-solve).
    part_of_free: Option<Vec<usize>>,
    /// The block solver of the partition, built on first use; `None` inside once it was found
    /// not to pay (the LU then serves).
    schur: Option<Option<SchurSolver>>,
    /// The last LU-path factorisation is the block solver's.
    schur_active: bool,
    pub n_factorisations: usize,
    /// Factorise the symmetric part as L·D·Lᵀ and refine on the rest (dynamics), with the LU
    /// as fallback (docs/theory/fem.md#sparse-linear-algebra).
    pub symmetric: bool,
    pub(crate) sym: Option<SymmetricSolver>,
    /// The last factorisation is the symmetric one.
    sym_active: bool,
    /// Factorisations left on the LU after a symmetric fallback.
    sym_pause: usize,
    /// The pattern is not structurally symmetric: LU only.
    sym_unusable: bool,
    /// Solves that fell back from the symmetric factor to the LU.
    pub n_symmetric_fallbacks: usize,
    /// Refinement sweeps of all symmetric solves.
    pub n_refinement_sweeps: usize,
    /// Symmetric solves that kept an earlier L·D·Lᵀ as the preconditioner.
    pub n_factor_reuses: usize,
    /// The next `factorize` must factorise afresh (no usable L·D·Lᵀ, or the last one has
    /// grown too stale).
    sym_refactor: bool,
    /// Refinement sweeps of the last solve with a fresh L·D·Lᵀ.
    sym_fresh_sweeps: usize,
    /// Solves with a kept L·D·Lᵀ that did not contract, so that the factor was replaced and
    /// the solve repeated.
    pub n_stale_failures: usize,
    /// Factorisations left that skip the kept L·D·Lᵀ after it failed, and the length of the
    /// next such pause (doubled at each failure in a row).
    sym_skip: usize,
    sym_backoff: usize,
    load_scratch: (Box<ElementLoad>, Box<ElementLoad>),
    /// When set, the cables' (and net triangles') elastic force is the discrete gradient between these start and
    /// end positions of the step (docs/theory/fem.md#energy-consistent-midpoint), evaluated
    /// in the configuration passed to `evaluate` (the midpoint).
    pub secant: Option<StepEnds>,
    /// When set, the cables' and twines' elastic force is the energy-consistent step force of
    /// HHT-α from these start positions and memories, the system being evaluated at the
    /// step's end (docs/theory/fem.md#energy-consistent-hht-alpha).
    pub hht: Option<crate::dynamics::HhtForces>,
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
