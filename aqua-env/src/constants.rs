//! Fluid constants and water depth (docs/theory/environment.md#fluid-constants).

use serde::Serialize;

/// Standard gravity [m/s²], sea-water density [kg/m³] and kinematic viscosity [m²/s]: the
/// defaults of `[sea]`, one value each for every crate (from `aqua-constants`).
pub use aqua_constants::{SEA_WATER_DENSITY, SEA_WATER_VISCOSITY, STANDARD_GRAVITY};

/// Water depth h [m]: a flat seabed at z = −h, or no seabed at all.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Depth {
    /// Flat seabed at z = −h, h > 0 [m].
    Finite(f64),
    /// Deep water: no seabed (allowed for waves only).
    Infinite,
}

impl Depth {
    /// The depth in metres, `None` for infinite depth.
    pub fn finite(self) -> Option<f64> {
        match self {
            Depth::Finite(h) => Some(h),
            Depth::Infinite => None,
        }
    }
}

/// The physical constants every load model reads (no module holds its own copy).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Constants {
    /// Gravitational acceleration g [m/s²].
    pub gravity: f64,
    /// Water density ρ_w [kg/m³].
    pub density: f64,
    /// Kinematic viscosity ν [m²/s].
    pub kinematic_viscosity: f64,
    /// Water depth.
    pub depth: Depth,
}

impl Default for Constants {
    fn default() -> Self {
        Self {
            gravity: STANDARD_GRAVITY,
            density: SEA_WATER_DENSITY,
            kinematic_viscosity: SEA_WATER_VISCOSITY,
            depth: Depth::Infinite,
        }
    }
}

impl Constants {
    /// Default constants with a finite depth h [m].
    pub fn with_depth(h: f64) -> Self {
        Self {
            depth: Depth::Finite(h),
            ..Self::default()
        }
    }
}
