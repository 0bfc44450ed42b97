//! # aqua-fem — cable structures in statics and dynamics
//!
//! Nets, ropes and moorings as chains of 2-node cable elements with three translational DOF
//! per node (large displacements), rotation-free bending hinges on three consecutive nodes
//! ([`ModelBuilder::add_bending`], docs/theory/fem.md#bending), point bodies on nodes, fixed and
//! prescribed nodes, and a penalty seabed. Water loads (drag, lift, inertia, buoyancy, added mass) come
//! from a [`LoadProvider`]; this crate knows only gravity, elasticity, point masses and the
//! seabed (theory: `docs/theory/fem.md`).
//!
//! ## Governing equations (SI, z up, z = 0 still water)
//!
//! Semi-discrete equation of motion on the free DOFs, unknown **positions** x:
//!
//! M·ẍ + q(x, ẋ, t) = 0,  q = f_int(x, ẋ) − f_bed(x, ẋ) − f_ext(x, ẋ, t)
//!
//! * Cable element (nodes a, b; L0, EA, r_c, c_a): l = |x_b − x_a|, e = (x_b − x_a)/l,
//!   ε = (l − L0)/L0, ε̇ = eᵀ(v_b − v_a)/L0, s = 1 if ε > 0 else r_c,
//!   T = s·EA·ε + d·c_a·ε̇ with d = s except on the ramp 0 < ε < 1e-5 where the damping grows
//!   from r_c to 1, f_int,a = −T·e, f_int,b = +T·e; tangent
//!   k = (s·EA + d′·c_a·ε̇)/L0·eeᵀ + T/l·(I − eeᵀ) (+ the small non-symmetric damping term),
//!   c = d·c_a/L0·eeᵀ.
//! * Net triangle (Priour, docs/theory/fem.md#net-triangle; corners x_k with mesh coordinates
//!   (U_k, V_k), shape gradients a_k, b_k, A_uv the (U, V) area): twine vectors
//!   u = Σ a_k·x_k, v = Σ b_k·x_k, each family A_uv cables of rest length l_p from 0 to u (v):
//!   E = A_uv·(W(|u|) + W(|v|)), f_int,k = A_uv·(a_k·T_u·û + b_k·T_v·v̂), exact 9×9 tangent;
//!   mass 2·A_uv·l_p·μ, a third per corner.
//! * Mass: lumped μL0/2 per node (default) or consistent μL0/6·[2I, I; I, 2I]; point masses and
//!   the provider's added-mass 3×3 blocks add per node.
//! * Bending hinge (nodes a, b, c; EI, as-built κ̄ and ℓ̄): t = ê₁·ê₂ of the edges
//!   e₁ = x_b − x_a, e₂ = x_c − x_b, |κb| = 2·tan(φ/2), W = EI/(2ℓ̄)·(|κb| − κ̄)², f_int = ∂W/∂x,
//!   exact 9×9 tangent; rotation invariant, torsion neglected.
//! * Rod (discrete elastic rod, docs/theory/fem.md#rod): one twist θ per edge (the first
//!   coordinate of an auxiliary carrier node), material frames (m1, m2) parallel transported
//!   from the last accepted state and turned by θ; at each vertex
//!   W = EI/(2l̄)·Σ_j |ω^j − ω̄^j|² + GJ/l̄·(m − m̄)² with the material curvatures
//!   ω^j = (κb·m2_j, −κb·m1_j), κb = 2·t_a×t_b/(1 + t_a·t_b), and the twist m across the
//!   vertex; exact 11×11 tangent by automatic differentiation; a discrete gradient per vertex
//!   in the energy-consistent midpoint rule.
//! * Rigid body (docs/theory/fem.md#rigid-bodies): a centre node with the mass M and a
//!   rotation carrier whose coordinates are a rotation vector ψ, R = exp([ψ − ψ_ref]×)·R_ref
//!   from the last accepted state; rotational inertia R_ref·I·R_refᵀ as a 3×3 mass block on
//!   the carrier with the gyroscopic moment ω×(I_w·ω); each held point joined by a rigid
//!   link W = ½k·|x_p − x_c − R·p̄|², exact 9×9 tangent by automatic differentiation.
//! * Gravity −μL0g/2 ẑ per element node and −m·g ẑ per point body; constant point forces.
//! * Seabed z_s = −depth: f_z = max(0, (k_b·δ − c_b·v_z)·d_c·L_i) for δ = z_s − z > 0.
//! * Seabed friction in dynamics (regularised Coulomb, docs/theory/fem.md#seabed-friction):
//!   f_a = −μ_a·N·clamp(v_a/v_c, −1, 1) along the horizontal line direction, f_t likewise with
//!   μ_t across it; omitted in statics.
//! * Water loads f_h(t, x, v) and their Jacobians −∂f_h/∂v (damping) and −∂f_h/∂x (stiffness)
//!   from the provider, finite differences element by element when a derivative is missing.
//!
//! **Statics** ([`solve_static`]): q(x, 0, t0) = 0 by Levenberg–Marquardt Newton steps
//! (J + μD)Δx = −r, D = Σ EA/L0 per node, accepted and μ adapted on the energy merit
//! Π = Σ W_e + seabed energy − f_frozen·x (backtracking on it before μ rises), μ → 0 near the
//! solution (steps too small for the merit's round-off are judged by ‖r‖); load continuation
//! only when the full load fails; converged when ‖r‖₂ ≤ ε_r·F_ref, F_ref = max(‖f_ext‖₂, floor)
//! (the loads, never the reactions, which may hold a pretension), and ‖Δx‖∞ ≤ 1e-6·L_ref, or
//! when ‖r‖₂ is at its round-off floor F_noise. Parts held by nothing, drifting sideways or
//! heavier than their full buoyancy are refused before solving. Progress and stopping through
//! [`solve_static_observed`]. Why the iteration count grows with the mesh (a straight step
//! that turns a stiff member over-stretches it, and the cone's shortest members turn most) and
//! why a mixed (position and tension) Newton, at most 6 iterations on a catenary at any EA,
//! does not yet help nets (its residual merit cannot see a slack node's fall):
//! docs/theory/fem.md#newton-region, #short-members and #mixed-statics.
//!
//! **Dynamics** ([`DynamicSolver`], HHT-α, α ∈ [0, 1/3], β = (1 + α)²/4, γ = ½ + α):
//!
//! M·a_{n+1} + (1 − α)·q_{n+1} + α·q_n = 0,
//! a_{n+1} = (x_{n+1} − x_n − Δt·v_n)/(βΔt²) − (1/(2β) − 1)·a_n,
//! v_{n+1} = v_n + Δt·[(1 − γ)·a_n + γ·a_{n+1}],
//!
//! Newton Jacobian J = M/(βΔt²) + (1 − α)·[K + γ/(βΔt)·C], adaptive halving of Δt.
//!
//! **Explicit** ([`ExplicitSolver`]): lumped mass, a = M⁻¹(−q), semi-implicit Euler or RK4,
//! Δt from a Gershgorin bound of the highest axial frequency.
//!
//! ## Linear algebra
//! The free-DOF Jacobian pattern is assembled once. Water-load Jacobians (lift, ∂f/∂x,
//! Reynolds terms) and the damping term of the cable tangent are not symmetric, and the
//! compressed geometric term makes K indefinite. Statics use faer's sparse **LU** (COLAMD
//! ordering, symbolic analysis once, numeric factorisation every Newton iteration). Dynamics by
//! default factorise the symmetric part S = ½(J + Jᵀ) as **L·D·Lᵀ** (AMD; simplicial or
//! supernodal by fill), keep that factor across iterations and steps while it stays a good
//! preconditioner, and refine y ← y + S⁻¹(b − J·y) to 1e-10, or, inside Newton, to 1 % of the
//! Newton tolerance, and only to a tenth of the remainder Newton's quadratic model predicts
//! while that is above the tolerance (inexact Newton, an Eisenstat–Walker forcing term), so
//! every Newton step is J's own; the LU takes over where the refinement does not contract
//! (docs/theory/fem.md#sparse-linear-algebra).
//!
//! ## Files
//! One file per physical law or algorithm: `model.rs` (model, builder), `cable.rs`,
//! `net_triangle.rs`, `bending.rs`, `rod.rs`, `rigid_body.rs`, `seabed.rs` (the seabed's contact law: force, tangent, energy; `[sea.seabed]`'s `SeabedSettings` and every seabed default), `friction.rs`
//! (seabed friction), `loads.rs` (the provider interface), `motion.rs`, `state.rs`;
//! `system/` (`dofs.rs` numbering and pattern, `assembly.rs`, `rods.rs`, `bodies.rs`, `net_triangles.rs`,
//! `load_derivatives.rs`, `linear_solver.rs`) with `symmetric.rs` (L·D·Lᵀ and refinement); `statics/`
//! (`mod.rs` the solver, `settings.rs`, `support.rs` the checks before a solve);
//! `dynamics/` (`settings.rs`, `step_control.rs`, `energy.rs`, `newton.rs`, and one file per
//! time scheme, `hht.rs` and `midpoint.rs`, dispatched by `scheme.rs`);
//! `line_relaxation.rs`; `explicit.rs`.
//!
//! ## Use
//! ```
//! use aqua_fem::*;
//! let mut b = ModelBuilder::new(Environment::default());
//! let top = b.add_node([0.0, 0.0, 0.0]).unwrap();
//! let tip = b.add_node([0.0, 0.0, -10.0]).unwrap();
//! let g = b.add_group("rope", CableSection::new(1e6, 0.5)).unwrap();
//! b.add_cable(top, tip, g, UnstretchedLength::Given(10.0)).unwrap();
//! b.add_point_body(PointBody { node: tip, mass: 10.0, force: [0.0; 3], seabed_stiffness: 0.0 }).unwrap();
//! b.fix(top, Dofs::ALL).unwrap();
//! let model = b.build().unwrap();
//! let stat = solve_static(&model, &mut NoLoads, &StaticSettings::default()).unwrap();
//! let mut dynamic = DynamicSolver::new(&model, DynamicSettings::new(0.01, 0.1), Some(&stat.state), &mut NoLoads).unwrap();
//! while !dynamic.is_finished() {
//!     let report = dynamic.step(&mut NoLoads).unwrap();
//!     let _top_tension = dynamic.outputs().tension[0];
//!     assert!(report.iterations <= 15);
//! }
//! ```

mod bending;
mod builder;
mod cable;
mod dual;
pub mod dynamics;
pub mod error;
pub mod explicit;
mod failure;
pub mod friction;
mod line_relaxation;
pub mod loads;
pub mod model;
pub mod motion;
mod net_triangle;
mod rigid_body;
mod rod;
mod seabed;
pub mod state;
pub mod statics;
mod symmetric;
mod system;

pub use bending::Hinge;
pub use dynamics::{
    CONTACT_IMPACT, CONTACT_LOSS_WARNING, ContactResolution, DEFAULT_ALPHA, DEFAULT_THETA,
    DynamicSettings, DynamicSolver, ENERGY_GROWTH_TOL, Energies, ExtremeResolution, GroupSnaps,
    LinearSolverKind, LinearSolverStats, MassMatrix, RESOLVED_PHASE, SNAP_EXCESS_WARNING,
    SnapExtreme, SnapResolution, Snapshot, StepControl, StepEvent, StepReport, TensionResolution,
};
pub use error::{FemError, LoadError, Result, StaticFailure, StepFailure};
pub use explicit::{ExplicitScheme, ExplicitSettings, ExplicitSolver};
pub use failure::{FailureKind, FailureReason, SchemeKind};
pub use friction::{DEFAULT_SLIP_VELOCITY, SeabedFriction};
pub use loads::{ElementLoad, LoadProvider, MAX_LOAD_DOFS, MAX_LOAD_NODES, NoLoads, Want};
pub use model::{
    AxialDamping, Cable, CableSection, DEFAULT_COMPRESSION_RATIO, DEFAULT_GRAVITY,
    DEFAULT_WATER_DENSITY, Dofs, Environment, Group, GroupId, Model, ModelBuilder, PointBody,
    RodSection, Seabed, Support, UnstretchedLength,
};
pub use motion::{ExternalMotion, Keyframes, Motion, TableSpline, smooth_ramp};
pub use net_triangle::{
    NetGroupId, NetTriangle, NetTriangleGroup, NetTriangleSection, NetTriangleTwines,
};
pub use rigid_body::{BodyPose, LINK_STIFFNESS_FACTOR, RigidBody, RigidBodySpec};
pub use rod::{EdgeFrame, RodEdge, RodVertex};
pub use seabed::{
    DEFAULT_BED_DAMPING, DEFAULT_BED_DAMPING_DEPTH, DEFAULT_BED_STIFFNESS, InvalidSeabedKey,
    SeabedSettings,
};
pub use state::{Outputs, State};
pub use statics::{
    StaticControl, StaticProgress, StaticReport, StaticSettings, StaticSolution, solve_static,
    solve_static_from, solve_static_observed,
};
