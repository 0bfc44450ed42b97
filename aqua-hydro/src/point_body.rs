//! Point bodies (buoys, sinkers): drag, inertia, added mass and buoyancy on one node
//! (docs/theory/hydrodynamics.md#point-bodies, docs/theory/farm.md#buoys).

use crate::buoyancy;
use crate::types::{M3, V3, Want, ZERO_SPEED};
use crate::wetted;

/// How a point body's submerged volume and wet projected area grow as it goes under.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointShape {
    /// A vertical prism of height h_p [m] centred on the node: volume and area both wet in
    /// proportion φ_p = clamp(ζ/h_p + ½, 0, 1) (h_p = 0: a step at the surface). Exact for a
    /// vertical cylinder of height h_p; the law of `[[point]]`.
    Prism {
        /// Vertical extent h_p [m].
        height: f64,
    },
    /// A sphere of radius R [m] centred on the node: submerged volume the spherical cap
    /// πh²(3R − h)/3 and wet projected area the circular segment of height h, with
    /// h = clamp(ζ + R, 0, 2R) the submergence of its lowest point.
    Sphere {
        /// Radius R [m].
        radius: f64,
    },
}

impl PointShape {
    /// Wet fractions at centre submergence ζ [m]: (φ_V, dφ_V/dζ, φ_A, dφ_A/dζ), φ_V of the
    /// volume, φ_A of the projected (drag) area.
    pub fn fractions(&self, zeta: f64) -> (f64, f64, f64, f64) {
        match *self {
            PointShape::Prism { height } => {
                let (f, d) = wetted::point(zeta, height);
                (f, d, f, d)
            }
            PointShape::Sphere { radius } => {
                let (fv, dv) = wetted::sphere(zeta, radius);
                let (fa, da) = wetted::section(zeta, radius);
                (fv, dv, fa, da)
            }
        }
    }
}

/// A point body's hydrodynamic data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointProps {
    /// Displaced volume V [m³] when fully submerged (a sphere: 4πR³/3).
    pub volume: f64,
    /// Submergence law.
    pub shape: PointShape,
    /// Isotropic drag area C_D·A [m²] when fully submerged.
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

/// F = φ_A·½ρ_w(C_D A)|U_r|U_r + φ_V·[ρ_w V(1 + C_a)ā_f + ρ_w g V ẑ], added mass
/// φ_V·ρ_w·V·C_a, with the wet fractions φ_V, φ_A of [`PointShape::fractions`] at the node's
/// submergence `zeta` = η − z [m].
pub fn point(
    props: &PointProps,
    zeta: f64,
    w: V3,
    acc: V3,
    rho: f64,
    g: f64,
    want: Want,
) -> PointLoad {
    let (phi_v, dphi_v, phi_a, dphi_a) = props.shape.fractions(zeta);
    let s = w.norm();
    let kd = 0.5 * rho * props.drag_area;
    let drag = kd * s * w;
    let volume_part =
        rho * props.volume * (1.0 + props.added_mass) * acc + buoyancy::force(rho, g, props.volume);
    let mut dfdw = M3::zeros();
    if want.dfdv && s >= ZERO_SPEED {
        let u = w / s;
        dfdw = phi_a * kd * s * (M3::identity() + u * u.transpose());
    }
    let mut dfdx = M3::zeros();
    if want.dfdx {
        // ζ = η − z: ∂/∂z = −∂/∂ζ.
        let col = -(dphi_a * drag + dphi_v * volume_part);
        for r in 0..3 {
            dfdx[(r, 2)] = col[r];
        }
    }
    PointLoad {
        force: phi_a * drag + phi_v * volume_part,
        dfdw,
        dfdx,
        added_mass: (phi_v * rho * props.volume * props.added_mass) * M3::identity(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn buoy_half_submerged_with_stiffness() {
        let p = PointProps {
            volume: 2.0,
            shape: PointShape::Prism { height: 1.0 },
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

    /// A sphere of radius R whose centre is ζ below the surface: buoyancy ρg·πh²(3R − h)/3
    /// with h = ζ + R, heave stiffness ρg·π(2Rh − h²) (the waterplane area), drag on the wet
    /// circular segment of the silhouette, added mass C_a ρ V_cap.
    #[test]
    fn sphere_cap_buoyancy_waterplane_and_segment_drag() {
        let (rho, g, r) = (1025.0, 9.81, 0.8);
        let v = 4.0 / 3.0 * PI * r * r * r;
        let p = PointProps {
            volume: v,
            shape: PointShape::Sphere { radius: r },
            drag_area: 0.5 * PI * r * r,
            added_mass: 0.5,
        };
        let want = Want {
            dfdv: true,
            dfdx: true,
        };
        for zeta in [-0.79, -0.5, -0.1, 0.0, 0.3, 0.7] {
            let h: f64 = zeta + r;
            let cap = PI * h * h * (3.0 * r - h) / 3.0;
            let waterplane = PI * (2.0 * r * h - h * h);
            let seg = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
            let u = 0.7;
            let l = point(&p, zeta, V3::new(u, 0.0, 0.0), V3::zeros(), rho, g, want);
            assert!(
                (l.force.z - rho * g * cap).abs() < 1e-9 * rho * g * v,
                "{zeta}"
            );
            assert!((l.dfdx[(2, 2)] + rho * g * waterplane).abs() < 1e-9 * rho * g * r * r);
            let drag = 0.5 * rho * 0.5 * seg * u * u;
            assert!((l.force.x - drag).abs() < 1e-9 * rho, "{zeta}");
            assert!((l.added_mass[(0, 0)] - 0.5 * rho * cap).abs() < 1e-9 * rho * v);
        }
        // Fully under and fully out.
        let l = point(&p, 2.0, V3::zeros(), V3::zeros(), rho, g, want);
        assert!((l.force.z - rho * g * v).abs() < 1e-9 * rho * g * v);
        assert_eq!(l.dfdx[(2, 2)], 0.0);
        let l = point(&p, -2.0, V3::zeros(), V3::zeros(), rho, g, want);
        assert_eq!(l.force.z, 0.0);
    }

    /// The position derivative of the force is the derivative of the force (central
    /// differences in z), drag and buoyancy together.
    #[test]
    fn sphere_position_derivative_matches_differences() {
        let p = PointProps {
            volume: 4.0 / 3.0 * PI,
            shape: PointShape::Sphere { radius: 1.0 },
            drag_area: 0.6,
            added_mass: 0.5,
        };
        let want = Want {
            dfdv: true,
            dfdx: true,
        };
        let (w, a) = (V3::new(0.4, -0.2, 0.1), V3::new(0.05, 0.0, -0.02));
        for zeta in [-0.6, -0.05, 0.4, 0.9] {
            let e = 1e-6;
            let f = |z: f64| point(&p, z, w, a, 1025.0, 9.81, want).force;
            // ∂F/∂z = −∂F/∂ζ
            let fd = -(f(zeta + e) - f(zeta - e)) / (2.0 * e);
            let l = point(&p, zeta, w, a, 1025.0, 9.81, want);
            for r in 0..3 {
                assert!(
                    (l.dfdx[(r, 2)] - fd[r]).abs() < 1e-6 * (1.0 + fd[r].abs()),
                    "{zeta} {r}: {} {}",
                    l.dfdx[(r, 2)],
                    fd[r]
                );
            }
        }
    }
}
