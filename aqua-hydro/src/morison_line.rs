//! Morison loads on one line element: drag, Froude–Krylov and hydrodynamic-mass inertia,
//! added mass and buoyancy, all scaled by the wetted fraction of the circular section
//! (docs/theory/hydrodynamics.md#morison-line-model, #line-jacobians).

use crate::buoyancy;
use crate::morison_coefficients::MorisonModel;
use crate::types::{M3, V3, Want, ZERO_SPEED};
use crate::wetted;
use std::f64::consts::PI;

/// Section and model data of a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineProps {
    /// Drag model.
    pub model: MorisonModel,
    /// Drag (hydrodynamic) diameter d_h [m].
    pub hydro_diameter: f64,
    /// Diameter for the Reynolds number d_Re [m].
    pub reynolds_diameter: f64,
    /// Volume diameter d_v [m] (buoyancy, inertia, added mass, wetted fraction).
    pub volume_diameter: f64,
    /// Unstretched length L0 [m].
    pub rest_length: f64,
    /// Normal added-mass coefficient C_a.
    pub added_mass: f64,
    /// Axial added-mass coefficient C_at.
    pub added_mass_axial: f64,
    /// Include the Froude–Krylov force (the "1" of C_m = 1 + C_a) on the normal acceleration.
    pub froude_krylov: bool,
    /// Drag length max(L − d_h, 0) instead of L.
    pub knot_correction: bool,
}

/// Result of one line evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineLoad {
    /// Total force on the element [N] (half to each node).
    pub force: V3,
    /// ∂F/∂U_r of the drag [N·s/m] (∂f_i/∂v_j = −J/4).
    pub dfdw: M3,
    /// ∂F/∂x_1, ∂F/∂x_2 [N/m].
    pub dfdx: [M3; 2],
    /// Added mass of the whole element [kg] (half to each node).
    pub added_mass: M3,
    /// Reynolds number s·d_Re/ν.
    pub reynolds: f64,
    /// Re was clamped / M5 capped.
    pub clamped: bool,
    /// M5's X was capped.
    pub capped: bool,
}

/// Loads on one line.
///
/// `x`: node positions [m]; `zeta`: nodal submergences [m]; `w`: relative velocity [m/s];
/// `acc`: mean fluid acceleration ā_f [m/s²]; constants ρ_w [kg/m³], ν [m²/s], g [m/s²].
pub fn line(
    props: &LineProps,
    x: [V3; 2],
    zeta: [f64; 2],
    w: V3,
    acc: V3,
    rho: f64,
    nu: f64,
    g: f64,
    want: Want,
) -> LineLoad {
    let d = x[1] - x[0];
    let len = d.norm();
    let e = if len > 1e-12 { d / len } else { V3::z() };
    let (phi, dphi) = wetted::line(zeta[0], zeta[1], 0.5 * props.volume_diameter);
    let av = 0.25 * PI * props.volume_diameter * props.volume_diameter;
    let vol = av * props.rest_length;
    let id = M3::identity();
    let ee = e * e.transpose();
    let pn = id - ee;

    // drag (per unit wetted fraction)
    let ell = if props.knot_correction {
        (len - props.hydro_diameter).max(0.0)
    } else {
        len
    };
    let s = w.norm();
    let mut out = LineLoad {
        force: V3::zeros(),
        dfdw: M3::zeros(),
        dfdx: [M3::zeros(); 2],
        added_mass: M3::zeros(),
        reynolds: s * props.reynolds_diameter / nu,
        clamped: false,
        capped: false,
    };
    let mut f_drag = V3::zeros();
    let mut dfdx2 = M3::zeros();
    if s >= ZERO_SPEED && ell > 0.0 && !matches!(props.model, MorisonModel::None) {
        let k = props.model.coefficients(out.reynolds);
        out.clamped = k.clamped;
        out.capped = k.capped;
        let kl = 0.5 * rho * props.hydro_diameter * ell;
        let ew = e.dot(&w);
        let wt = ew * e;
        let wn = w - wt;
        let wnn = wn.norm();
        let wtn = ew.abs();
        f_drag = kl * (k.cn * wnn * wn + k.ct * wtn * wt);
        let nhat = if wnn > 0.0 { wn / wnn } else { V3::zeros() };
        if want.dfdv {
            let u = w / s;
            let ds = props.reynolds_diameter / nu;
            let mut inner = 2.0 * k.ct * wtn * ee
                + (ds * k.dcn * wnn * wn + ds * k.dct * wtn * wt) * u.transpose();
            if wnn > 0.0 {
                inner += k.cn * wnn * (pn + nhat * nhat.transpose());
            }
            out.dfdw = phi * kl * inner;
        }
        if want.dfdx {
            // ∂F/∂e (Re depends on |w| only), then ∂e/∂x2 = P_n/L, ∂ℓ/∂x2 = eᵀ
            let mut dfde = k.ct * wtn * (2.0 * e * w.transpose() + ew * id);
            if wnn > 0.0 {
                dfde -= k.cn * wnn * (id + nhat * nhat.transpose()) * (ew * id + e * w.transpose());
            }
            dfdx2 = f_drag * e.transpose() / ell + kl * dfde * pn / len;
        }
    }

    // inertia: Froude–Krylov + hydrodynamic mass on the normal part, C_at on the axial part
    let cn_i = props.added_mass + if props.froude_krylov { 1.0 } else { 0.0 };
    let ea = e.dot(&acc);
    let f_inertia = rho * vol * (cn_i * (acc - ea * e) + props.added_mass_axial * ea * e);
    let f_buoy = buoyancy::force(rho, g, vol);
    let f_tilde = f_drag + f_inertia + f_buoy;
    out.force = phi * f_tilde;
    out.added_mass = (phi * rho * vol) * (props.added_mass * pn + props.added_mass_axial * ee);
    if want.dfdx {
        if len > 1e-12 {
            let dfde_i =
                rho * vol * (props.added_mass_axial - cn_i) * (ea * id + e * acc.transpose());
            dfdx2 += dfde_i * pn / len;
        }
        let b = phi * dfdx2;
        out.dfdx = [-b, b];
        for j in 0..2 {
            let col = -dphi[j] * f_tilde;
            for r in 0..3 {
                out.dfdx[j][(r, 2)] += col[r];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::morison_coefficients::MorisonModel;
    use proptest::prelude::*;

    const RHO: f64 = 1025.0;
    const NU: f64 = 1.19e-6;
    const G: f64 = 9.80665;
    const ALL: Want = Want {
        dfdv: true,
        dfdx: true,
    };

    fn props(model: MorisonModel) -> LineProps {
        LineProps {
            model,
            hydro_diameter: 0.05,
            reynolds_diameter: 0.05,
            volume_diameter: 0.05,
            rest_length: 2.0,
            added_mass: 1.0,
            added_mass_axial: 0.2,
            froude_krylov: true,
            knot_correction: false,
        }
    }

    fn rel_err(a: &M3, b: &M3) -> f64 {
        (a - b).norm() / a.norm().max(b.norm()).max(1e-300)
    }

    #[test]
    fn worked_drag_case() {
        // docs/theory/hydrodynamics.md#worked-load-cases: M1, d_h = 0.05, nodes (0,0,−5),
        // (1,0,−5−√3), U = (0.4,0,0)
        let mut p = props(MorisonModel::M1);
        p.added_mass = 0.0;
        p.added_mass_axial = 0.0;
        p.froude_krylov = false;
        p.volume_diameter = 1e-9; // no buoyancy worth counting
        let x = [
            V3::new(0.0, 0.0, -5.0),
            V3::new(1.0, 0.0, -5.0 - 3f64.sqrt()),
        ];
        let l = line(
            &p,
            x,
            [5.0, 6.7],
            V3::new(0.4, 0.0, 0.0),
            V3::zeros(),
            RHO,
            NU,
            0.0,
            ALL,
        );
        let expect = V3::new(6.4937674799, 0.0, 3.5124647922);
        assert!((l.force - expect).norm() < 5e-10, "{:?}", l.force);
    }

    fn fd_dfdw(p: &LineProps, x: [V3; 2], z: [f64; 2], w: V3) -> (M3, M3) {
        // g = 0: a constant buoyancy would only add round-off to the differences
        const G: f64 = 0.0;
        let exact = line(p, x, z, w, V3::zeros(), RHO, NU, G, ALL).dfdw;
        let h = 1e-6 * w.norm();
        let mut fd = M3::zeros();
        for k in 0..3 {
            let (mut wp, mut wm) = (w, w);
            wp[k] += h;
            wm[k] -= h;
            let fp = line(p, x, z, wp, V3::zeros(), RHO, NU, G, ALL).force;
            let fm = line(p, x, z, wm, V3::zeros(), RHO, NU, G, ALL).force;
            fd.set_column(k, &((fp - fm) / (2.0 * h)));
        }
        (exact, fd)
    }

    #[test]
    fn velocity_jacobian_matches_central_differences() {
        let x = [V3::new(0.1, 0.2, -3.0), V3::new(1.3, -0.4, -2.2)];
        let models = [
            MorisonModel::M1,
            MorisonModel::M2,
            MorisonModel::M3,
            MorisonModel::M4,
            MorisonModel::M5 { solidity: 0.2 },
            MorisonModel::Const { cn: 1.1, ct: 0.05 },
        ];
        // speeds that put Re on different branches of M3/M4 (d = 0.05 m → Re = 4.2e4·s)
        for (i, model) in models.into_iter().enumerate() {
            for w in [
                V3::new(0.5, 0.1, -0.05),
                V3::new(-0.003, 0.001, 0.002),
                V3::new(2.0, -8.0, 1.0),
                V3::new(1e-5, 2e-5, 0.0),
            ] {
                let mut p = props(model);
                p.reynolds_diameter = if i == 4 { 0.002 } else { 0.05 };
                let (exact, fd) = fd_dfdw(&p, x, [3.0, 2.2], w);
                assert!(
                    rel_err(&exact, &fd) < 1e-6,
                    "{model:?} {w:?}: {exact} vs {fd}"
                );
            }
        }
    }

    #[test]
    fn constant_coefficient_jacobian_is_symmetric_psd() {
        let x = [V3::new(0.0, 0.0, -3.0), V3::new(1.0, 0.5, -2.0)];
        let (j, _) = fd_dfdw(
            &props(MorisonModel::M1),
            x,
            [3.0, 2.0],
            V3::new(0.3, -0.1, 0.2),
        );
        assert!(rel_err(&j, &j.transpose()) < 1e-14);
        assert!(j.symmetric_eigenvalues().iter().all(|e| *e >= -1e-12));
    }

    #[test]
    fn position_jacobian_matches_central_differences() {
        for (model, knot) in [(MorisonModel::M1, false), (MorisonModel::M4, true)] {
            let mut p = props(model);
            p.knot_correction = knot;
            p.volume_diameter = 0.3;
            let w = V3::new(0.4, -0.2, 0.1);
            let acc = V3::new(0.3, 0.1, -0.2);
            let x = [V3::new(0.1, 0.2, -0.05), V3::new(1.3, -0.4, 0.1)];
            let zeta = |x: &[V3; 2]| [-x[0].z, -x[1].z];
            let exact = line(&p, x, zeta(&x), w, acc, RHO, NU, G, ALL).dfdx;
            let h = 1e-6;
            for j in 0..2 {
                let mut fd = M3::zeros();
                for k in 0..3 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j][k] += h;
                    xm[j][k] -= h;
                    let fp = line(&p, xp, zeta(&xp), w, acc, RHO, NU, G, ALL).force;
                    let fm = line(&p, xm, zeta(&xm), w, acc, RHO, NU, G, ALL).force;
                    fd.set_column(k, &((fp - fm) / (2.0 * h)));
                }
                assert!(
                    rel_err(&exact[j], &fd) < 1e-6,
                    "{model:?} node {j}: {} vs {fd}",
                    exact[j]
                );
            }
            // fully submerged: exact
            let x = [V3::new(0.1, 0.2, -3.0), V3::new(1.3, -0.4, -2.2)];
            let exact = line(&p, x, zeta(&x), w, acc, RHO, NU, G, ALL).dfdx;
            for j in 0..2 {
                let mut fd = M3::zeros();
                for k in 0..3 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j][k] += h;
                    xm[j][k] -= h;
                    let fp = line(&p, xp, zeta(&xp), w, acc, RHO, NU, G, ALL).force;
                    let fm = line(&p, xm, zeta(&xm), w, acc, RHO, NU, G, ALL).force;
                    fd.set_column(k, &((fp - fm) / (2.0 * h)));
                }
                assert!(
                    rel_err(&exact[j], &fd) < 1e-6,
                    "{model:?} node {j}: {} vs {fd}",
                    exact[j]
                );
            }
        }
    }

    #[test]
    fn buoyancy_and_added_mass() {
        let p = props(MorisonModel::None);
        let x = [V3::new(0.0, 0.0, -3.0), V3::new(2.0, 0.0, -3.0)];
        let l = line(&p, x, [3.0, 3.0], V3::zeros(), V3::zeros(), RHO, NU, G, ALL);
        let vol = PI / 4.0 * 0.05 * 0.05 * 2.0;
        assert!((l.force.z - RHO * G * vol).abs() < 1e-12);
        assert!((l.added_mass[(1, 1)] - RHO * vol * 1.0).abs() < 1e-12);
        assert!((l.added_mass[(0, 0)] - RHO * vol * 0.2).abs() < 1e-12);
        assert_eq!(l.added_mass[(0, 1)], 0.0);
    }

    proptest! {
        #[test]
        fn drag_opposes_nothing_and_dissipates(
            wx in -2.0f64..2.0, wy in -2.0f64..2.0, wz in -2.0f64..2.0, mi in 0usize..4,
        ) {
            // drag power F·U_r ≥ 0 and the damping −∂f/∂v has a non-negative symmetric part for
            // constant coefficients
            let model = [MorisonModel::M1, MorisonModel::M2, MorisonModel::M4, MorisonModel::M3][mi];
            let mut p = props(model);
            p.volume_diameter = 1e-9;
            let x = [V3::new(0.0, 0.0, -3.0), V3::new(0.6, 0.8, -3.0)];
            let w = V3::new(wx, wy, wz);
            let l = line(&p, x, [3.0, 3.0], w, V3::zeros(), RHO, NU, 0.0, ALL);
            prop_assert!(l.force.dot(&w) >= -1e-12);
            if mi < 2 {
                let sym = 0.5 * (l.dfdw + l.dfdw.transpose());
                prop_assert!(sym.symmetric_eigenvalues().iter().all(|e| *e >= -1e-9));
            }
        }
    }
}
