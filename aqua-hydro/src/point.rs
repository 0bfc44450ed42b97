//! Point bodies (buoys, sinkers): drag, inertia, added mass and buoyancy on one node
//! (docs/theory/hydrodynamics.md#point-bodies).

use crate::panel::{M3, V3, Want, ZERO_SPEED};
use crate::wetted;

/// A point body's hydrodynamic data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointProps {
    /// Displaced volume V [m³].
    pub volume: f64,
    /// Vertical extent h_p [m] for partial submergence (0: a step at the surface).
    pub height: f64,
    /// Isotropic drag area C_D·A [m²].
    pub drag_area: f64,
    /// Added-mass coefficient C_a,p.
    pub added_mass: f64,
}

/// Result of one point evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLoad {
    /// Force [N].
    pub force: V3,
    /// ∂F/∂U_r [N·s/m] (∂f/∂v = −J).
    pub dfdw: M3,
    /// ∂F/∂x [N/m].
    pub dfdx: M3,
    /// Added mass [kg].
    pub added_mass: M3,
}

/// F = φ_p·[½ρ_w(C_D A)|U_r|U_r + ρ_w V(1 + C_a)ā_f + ρ_w g V ẑ].
pub fn point(
    props: &PointProps,
    zeta: f64,
    w: V3,
    acc: V3,
    rho: f64,
    g: f64,
    want: Want,
) -> PointLoad {
    let (phi, dphi) = wetted::point(zeta, props.height);
    let s = w.norm();
    let kd = 0.5 * rho * props.drag_area;
    let f_tilde = kd * s * w
        + rho * props.volume * (1.0 + props.added_mass) * acc
        + V3::new(0.0, 0.0, rho * g * props.volume);
    let mut dfdw = M3::zeros();
    if want.dfdv && s >= ZERO_SPEED {
        let u = w / s;
        dfdw = phi * kd * s * (M3::identity() + u * u.transpose());
    }
    let mut dfdx = M3::zeros();
    if want.dfdx {
        let col = -dphi * f_tilde;
        for r in 0..3 {
            dfdx[(r, 2)] = col[r];
        }
    }
    PointLoad {
        force: phi * f_tilde,
        dfdw,
        dfdx,
        added_mass: (phi * rho * props.volume * props.added_mass) * M3::identity(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buoy_half_submerged_with_stiffness() {
        let p = PointProps {
            volume: 2.0,
            height: 1.0,
            drag_area: 0.5,
            added_mass: 0.5,
        };
        let want = Want {
            dfdv: true,
            dfdx: true,
        };
        let l = point(&p, 0.0, V3::zeros(), V3::zeros(), 1025.0, 9.81, want);
        assert!((l.force.z - 0.5 * 1025.0 * 9.81 * 2.0).abs() < 1e-9);
        // heave stiffness −ρ g V / h_p
        assert!((l.dfdx[(2, 2)] + 1025.0 * 9.81 * 2.0).abs() < 1e-9);
        assert!((l.added_mass[(0, 0)] - 0.5 * 1025.0 * 2.0 * 0.5).abs() < 1e-9);
        let l = point(
            &p,
            5.0,
            V3::new(1.0, 0.0, 0.0),
            V3::zeros(),
            1025.0,
            9.81,
            want,
        );
        assert!((l.force.x - 0.5 * 1025.0 * 0.5).abs() < 1e-9);
        assert!((l.dfdw[(0, 0)] - 1025.0 * 0.5).abs() < 1e-9);
    }
}
