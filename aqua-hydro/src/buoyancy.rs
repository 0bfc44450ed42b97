//! Buoyancy: the weight of the displaced water, ρ_w·g·V·ẑ on a fully submerged volume V
//! (docs/theory/hydrodynamics.md#buoyancy).
//!
//! Where the pieces are:
//! * the displaced volume: lines A_v·L0 ([`crate::morison_line`]), point bodies V
//!   ([`crate::point_body`]); nets carry theirs on the twine lines
//!   ([`crate::assembly::LoadAssembly::net_summary`] compares it with the physical twines);
//! * the wetted fraction that scales it, φ̄ of a line or φ_V of a point body, and its
//!   derivative with respect to the submergence ([`crate::wetted`]);
//! * the force ([`force`]), multiplied by that fraction together with the element's other
//!   volume forces; its position derivative −∂φ/∂ζ·F is the waterplane stiffness.

use crate::types::V3;

/// Buoyancy of a fully submerged volume `volume` [m³] in water of density `rho` [kg/m³] under
/// gravity `g` [m/s²]: ρ_w·g·V upwards [N].
pub fn force(rho: f64, g: f64, volume: f64) -> V3 {
    V3::new(0.0, 0.0, rho * g * volume)
}
