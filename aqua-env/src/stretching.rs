//! Kinematics in the surface region: where linear wave kinematics are evaluated for a point
//! under the instantaneous surface (docs/theory/environment.md#surface-stretching).

use crate::constants::Depth;
use serde::{Deserialize, Serialize};

/// How the evaluation height z_s is chosen for a wet point (z ≤ η).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stretching {
    /// z_s = z: linear theory; above z = 0 the profile keeps growing like e^{kz}.
    None,
    /// z_s = min(z, 0): constant continuation above still water.
    Vertical,
    /// Wheeler: z_s = h(z − η)/(h + η) (finite h) or z − η (infinite h); maps [−h, η] → [−h, 0].
    Wheeler,
}

impl Stretching {
    /// The evaluation height z_s [m] for a point at height z under a surface at η.
    #[inline]
    pub fn apply(self, z: f64, eta: f64, depth: Depth) -> f64 {
        match self {
            Stretching::None => z,
            Stretching::Vertical => z.min(0.0),
            Stretching::Wheeler => match depth {
                Depth::Finite(h) => h * (z - eta) / (h + eta),
                Depth::Infinite => z - eta,
            },
        }
    }

    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Stretching::None => "none",
            Stretching::Vertical => "vertical",
            Stretching::Wheeler => "wheeler",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheeler_maps_surface_and_bed() {
        let d = Depth::Finite(30.0);
        for eta in [-1.3, 0.0, 0.7, 2.5] {
            assert!(Stretching::Wheeler.apply(eta, eta, d).abs() < 1e-14);
            assert!((Stretching::Wheeler.apply(-30.0, eta, d) + 30.0).abs() < 1e-12);
        }
        assert_eq!(Stretching::Wheeler.apply(0.5, 0.5, Depth::Infinite), 0.0);
        assert_eq!(Stretching::Vertical.apply(0.4, 0.5, d), 0.0);
        assert_eq!(Stretching::None.apply(0.4, 0.5, d), 0.4);
    }
}
