//! aqua-hydro — loads from the water on nets, lines and point bodies (theory:
//! `docs/theory/hydrodynamics.md`). It knows nothing about solvers: given a sea
//! ([`aqua_env::Sea`]), a time, node positions and velocities, it returns nodal forces,
//! added-mass blocks and the closed-form derivatives ∂f/∂v (hydrodynamic damping) and ∂f/∂x.
//!
//! Conventions: SI units, z up, z = 0 at still water; forces act on the structure.
//!
//! Governing equations (ρ_w, ν, g from the sea; r the wake factor of the element):
//! - Relative velocity U_r = r·mean U_c + mean u_w − mean v, s = |U_r|, û = U_r/s; zero
//!   drag below s = 1e-12 m/s; Reynolds numbers clamped to 1e7.
//! - Net panels ([`net_panel`]; triangles, quads as four triangles of weight ½), oriented
//!   normal n (n·U_r ≥ 0), c = cos θ = n·û: F = ½ρ_w·φ·A·[C_D·s·U_r + G·(s²n − (n·U_r)U_r)], G = C_L/sin θ, with the
//!   screen models S1–S6, bi2014 and const of [`screen`]; S4 in its native form
//!   ½ρ_w·φ·A·[C_n(n·U_r)²n + C_t|U_t|U_t]. φ is the exact wet-area fraction.
//! - Lines (Morison, [`morison_line`]): F = ½ρ_w·φ̄·d_h·ℓ·[C_n|U_n|U_n + C_t|U_t|U_t] plus
//!   ρ_w·φ̄·A_v·L0·[(1 + C_a)P_n + C_at·P_t]·ā_f plus ρ_w·g·A_v·L0·φ̄·ẑ, added mass
//!   ρ_w·φ̄·A_v·L0·(C_a·P_n + C_at·P_t); models M1–M5 and const of [`morison_coefficients`].
//! - Point bodies ([`point_body`]): F = φ_A·½ρ_w(C_D A)|U_r|U_r + φ_V·[ρ_w V(1 + C_a)ā_f
//!   + ρ_w g V ẑ], φ_V, φ_A the wet fractions of volume and projected area (a prism's linear law, or a sphere's cap).
//! - Buoyancy ([`buoyancy`]): ρ_w·g·V·ẑ of the displaced volume, times the wetted fraction of
//!   [`wetted`] (circular sections, point bodies) like every volume force.
//! - Wake: r = 1, clamp(f), 1 − 0.46·C_D0 (Løland) or clamp((c + 0.05 − 0.38Sn)/(c + 0.05))
//!   (Cheng) on the downstream half of each cage, (c_e − o)_h·û_h > δ ([`wake`]); between
//!   cages, r_c² of every other cage c with the element in its downstream strip of half-width
//!   R_c, the factors multiplying ([`cage_wake`]).
//! - Linearisation: with J_w = ∂F/∂U_r of an element of n nodes and equal force shares,
//!   ∂f_i/∂v_j = −J_w/n² for every node pair
//!   (docs/theory/hydrodynamics.md#distribution-to-nodes).
//!
//! Entry point: [`LoadAssembly`], built once from [`Elements`]; see [`assembly`] for the
//! output layout.

pub mod assembly;
pub mod buoyancy;
pub mod cage_wake;
pub mod coefficient_grid;
pub mod coefficient_report;
mod coefficient_text;
pub mod coefficients;
pub mod cylinder;
pub mod error;
pub mod morison_coefficients;
pub mod morison_line;
pub mod net_panel;
pub mod net_triangle;
pub mod point_body;
pub mod screen;
pub mod types;
pub mod wake;
pub mod wetted;

pub use assembly::{
    Block, Diagnostics, ElementOutput, Elements, LineElement, LoadAssembly, NetPanel, NetSummary,
    Outputs, PanelNodes, PointElement, WakeGroup,
};
pub use cage_wake::{CageShadow, CageWake, CageWakeSource};
pub use error::HydroError;
pub use morison_coefficients::{MorisonCoeffs, MorisonModel, MorisonModelId};
pub use morison_line::LineProps;
pub use net_panel::NetProps;
pub use net_triangle::TwineMap;
pub use point_body::{PointProps, PointShape};
pub use screen::{ScreenModel, ScreenModelId};
pub use types::{Want, ZERO_SPEED};
pub use wake::{Wake, WakeCell, WakeModel, WakeModelId, WakeSpec, WakeUpdate};
