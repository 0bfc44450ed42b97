//! The physical constants of aqua, one value each (docs/README.md#conventions, "Physical
//! constants").
//!
//! This crate has no dependencies so that every crate can take its constants from here:
//! aqua-env (which owns the sea and re-exports them as its defaults), aqua-fem (the defaults of
//! a structure built without a sea) and aqua-mesh. A scene's values are the sea's (`[sea]`), and
//! aqua-sim passes them to the structure; no crate keeps a private copy of a constant.

/// Standard gravity g_n [m/s²] (the conventional value of the CGPM, 1901).
pub const STANDARD_GRAVITY: f64 = 9.80665;
/// Default sea-water density ρ_w [kg/m³].
pub const SEA_WATER_DENSITY: f64 = 1025.0;
/// Default kinematic viscosity of sea water at 15 °C ν [m²/s].
pub const SEA_WATER_VISCOSITY: f64 = 1.19e-6;
