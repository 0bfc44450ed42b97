//! Screen-model loads on one triangle of net (docs/theory/hydrodynamics.md#net-panels,
//! #panel-velocity-jacobian, #panel-position-jacobian).
//!
//! F = ½ρ_w·φ·A·[C_D·s·U_r + G·(s²·n − (n·U_r)·U_r)], G = C_L/sin θ, n the normal oriented
//! downstream; S4 in its native form F = ½ρ_w·φ·A·[C_n(n·U_r)²n + C_t|U_t|U_t].

use crate::screen::{LIFT_EPS, ScreenModel, fridman};
use crate::types::{M3, V3, Want, ZERO_SPEED};
use crate::wetted;

/// Net properties a triangle needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetProps {
    /// Screen model.
    pub model: ScreenModel,
    /// Solidity Sn (0 < Sn < 1).
    pub solidity: f64,
    /// Physical twine diameter dw0 [m] (Reynolds numbers).
    pub twine_diameter: f64,
}

/// Result of one triangle: total force on the (weighted) triangle, ∂F/∂U_r, ∂F/∂p_j.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleLoad {
    /// Force F [N].
    pub force: V3,
    /// ∂F/∂U_r [N·s/m] (∂f_i/∂v_j = −J/9 for the three nodes).
    pub dfdw: M3,
    /// ∂F/∂p_j [N/m] (fluid kinematics held fixed).
    pub dfdp: [M3; 3],
    /// Reynolds number s·dw0/ν seen.
    pub reynolds: f64,
}

impl Default for TriangleLoad {
    fn default() -> Self {
        Self {
            force: V3::zeros(),
            dfdw: M3::zeros(),
            dfdp: [M3::zeros(); 3],
            reynolds: 0.0,
        }
    }
}

/// Cross-product matrix [v]×.
#[inline]
pub(crate) fn skew(v: &V3) -> M3 {
    M3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Loads on one triangle.
///
/// * `p`: node positions [m]; `zeta`: nodal submergences [m];
/// * `w`: relative velocity U_r = ū_f − v̄ [m/s];
/// * `weight`: 1 for a mesh triangle, ½ for a sub-triangle of a quad;
/// * `rho` [kg/m³], `nu` [m²/s].
pub fn triangle(
    net: &NetProps,
    p: [V3; 3],
    zeta: [f64; 3],
    w: V3,
    weight: f64,
    rho: f64,
    nu: f64,
    want: Want,
) -> TriangleLoad {
    let mut out = TriangleLoad::default();
    let a0 = 0.5 * (p[1] - p[0]).cross(&(p[2] - p[0]));
    let area = a0.norm();
    let s = w.norm();
    if area <= 0.0 || s < ZERO_SPEED {
        return out;
    }
    let (phi, dphi) = wetted::triangle(zeta);
    if phi == 0.0 && !want.dfdx {
        return out;
    }
    let u = w / s;
    let n0 = a0 / area;
    let sign = if n0.dot(&w) >= 0.0 { 1.0 } else { -1.0 };
    let n = sign * n0;
    let c = n.dot(&u).clamp(0.0, 1.0);
    let m = n - c * u;
    let sigma = m.norm();
    let re = s * net.twine_diameter / nu;
    out.reynolds = re;
    let half_rho = 0.5 * rho * weight;
    // force per unit wetted fraction, and its area-free factor
    let kt = half_rho * area;
    let id = M3::identity();
    let uu = u * u.transpose();
    let (f_tilde, jw_tilde, dfda_tilde) = if let ScreenModel::S4 = net.model {
        let nt = fridman(net.solidity, re);
        let nw = n.dot(&w);
        let wt = w - nw * n;
        let wtn = wt.norm();
        let f = kt * (nt.cn * nw * nw * n + nt.ct * wtn * wt);
        let mut jw = M3::zeros();
        let mut da = M3::zeros();
        if want.dfdv {
            let pt = id - n * n.transpose();
            let mut inner = 2.0 * nt.cn * nw * n * n.transpose()
                + (nt.s_cn_s / s * nw * nw * n + nt.s_ct_s / s * wtn * wt) * u.transpose();
            if wtn > 0.0 {
                let t = wt / wtn;
                inner += nt.ct * wtn * (pt + t * t.transpose());
            }
            jw = (kt * phi) * inner;
        }
        if want.dfdx {
            let mut inner =
                nt.cn * (2.0 * nw * n * w.transpose() + nw * nw * (id - 2.0 * n * n.transpose()));
            if wtn > 0.0 {
                let t = wt / wtn;
                inner += nt.ct
                    * wtn
                    * (wt * n.transpose()
                        - (id + t * t.transpose())
                            * (nw * id + n * w.transpose() - 2.0 * nw * n * n.transpose()));
            }
            da = half_rho * inner;
        }
        (f, jw, da)
    } else {
        let k = net.model.coeffs(c, sigma, net.solidity, re);
        let singular = matches!(net.model, ScreenModel::S5 | ScreenModel::Const { .. });
        let lift_on = !(singular && sigma <= LIFT_EPS);
        let g = if lift_on { k.g } else { 0.0 };
        let f = kt * (k.cd * s * w + g * s * s * m);
        let mut jw = M3::zeros();
        let mut da = M3::zeros();
        if want.dfdv {
            // J/K = s·C_D(I + ûûᵀ) + s²C_D,s ûûᵀ + s·C_D,c û mᵀ
            //     + s·G(2nûᵀ − ûnᵀ − cI) + s·G_c m mᵀ + s²G_s m ûᵀ
            // grouped as a·I + û pᵀ + n qᵀ + m rᵀ (three outer products)
            let (sg, sgc, sgs) = if lift_on {
                (s * g, s * k.g_c, s * k.s_g_s)
            } else {
                (0.0, 0.0, 0.0)
            };
            let a = s * k.cd - sg * c;
            let kphi = kt * phi;
            let pv = (s * (k.cd + k.s_cd_s)) * u + (s * k.cd_c) * m - sg * n;
            let qv = (2.0 * sg) * u;
            let rv = sgc * m + sgs * u;
            for r in 0..3 {
                for col in 0..3 {
                    jw[(r, col)] = kphi * (u[r] * pv[col] + n[r] * qv[col] + m[r] * rv[col]);
                }
                jw[(r, r)] += kphi * a;
            }
        }
        if want.dfdx {
            let q = u - c * n;
            let mut inner = u * (k.cd_c * q + k.cd * n).transpose();
            if lift_on {
                inner += k.g_c * m * q.transpose() + g * (id - uu);
            }
            da = half_rho * s * s * inner;
        }
        (f, jw, da)
    };
    out.force = phi * f_tilde;
    if want.dfdv {
        out.dfdw = jw_tilde;
    }
    if want.dfdx {
        // a = sign·a0; ∂a0/∂p1 = ½[p3 − p2]×, ∂a0/∂p2 = ½[p1 − p3]×, ∂a0/∂p3 = ½[p2 − p1]×
        let da = (0.5 * sign * phi) * dfda_tilde;
        let edges = [p[2] - p[1], p[0] - p[2], p[1] - p[0]];
        for j in 0..3 {
            let mut b = da * skew(&edges[j]);
            // ζ_j = η_j − z_j: ∂F/∂z_j = −F̃·∂φ/∂ζ_j
            if dphi[j] != 0.0 {
                let col = -dphi[j] * f_tilde;
                for r in 0..3 {
                    b[(r, 2)] += col[r];
                }
            }
            out.dfdp[j] = b;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::screen::ScreenModelId;
    use proptest::prelude::*;

    const RHO: f64 = 1025.0;
    const NU: f64 = 1.19e-6;
    const ALL: Want = Want {
        dfdv: true,
        dfdx: true,
    };

    fn models() -> Vec<ScreenModel> {
        vec![
            ScreenModel::S1,
            ScreenModel::S2,
            ScreenModel::S3 { cyl_cd: None },
            ScreenModel::S3 { cyl_cd: Some(1.2) },
            ScreenModel::S4,
            ScreenModel::S5,
            ScreenModel::S6 { cyl_cd: None },
            ScreenModel::Bi2014,
            ScreenModel::Const { cd: 0.3, cl: 0.05 },
        ]
    }

    fn net(model: ScreenModel) -> NetProps {
        NetProps {
            model,
            solidity: 0.22,
            twine_diameter: 0.0024,
        }
    }

    fn tri() -> [V3; 3] {
        [
            V3::new(0.1, -0.2, -1.0),
            V3::new(0.9, 0.3, -1.4),
            V3::new(-0.2, 0.7, -0.3),
        ]
    }

    fn rel_err(a: &M3, b: &M3) -> f64 {
        (a - b).norm() / a.norm().max(b.norm()).max(1e-300)
    }

    /// Central differences of F in U_r, compared to the closed form.
    fn check_dfdw(model: ScreenModel, w: V3, zeta: [f64; 3]) -> f64 {
        let n = net(model);
        // polynomial fits (S3/S6 C_cyl, S5) lose digits to cancellation: relative step 1e-4,
        // with Richardson extrapolation below for the truncation error
        let h_rel = 1e-4;
        let h = h_rel * w.norm();
        let exact = triangle(&n, tri(), zeta, w, 0.5, RHO, NU, ALL).dfdw;
        let central = |h: f64| {
            let mut fd = M3::zeros();
            for k in 0..3 {
                let mut wp = w;
                let mut wm = w;
                wp[k] += h;
                wm[k] -= h;
                let fp = triangle(&n, tri(), zeta, wp, 0.5, RHO, NU, ALL).force;
                let fm = triangle(&n, tri(), zeta, wm, 0.5, RHO, NU, ALL).force;
                fd.set_column(k, &((fp - fm) / (2.0 * h)));
            }
            fd
        };
        // Richardson extrapolation of the central differences removes their O(h²) error
        let fd = (4.0 * central(0.5 * h) - central(h)) / 3.0;
        rel_err(&exact, &fd)
    }

    fn check_dfdp(model: ScreenModel, w: V3, zeta: [f64; 3]) -> f64 {
        let n = net(model);
        let exact = triangle(&n, tri(), zeta, w, 1.0, RHO, NU, ALL).dfdp;
        let h = 1e-6;
        let mut worst: f64 = 0.0;
        for j in 0..3 {
            let mut fd = M3::zeros();
            for k in 0..3 {
                let (mut pp, mut pm) = (tri(), tri());
                pp[j][k] += h;
                pm[j][k] -= h;
                let (mut zp, mut zm) = (zeta, zeta);
                if k == 2 {
                    zp[j] -= h;
                    zm[j] += h;
                }
                let fp = triangle(&n, pp, zp, w, 1.0, RHO, NU, ALL).force;
                let fm = triangle(&n, pm, zm, w, 1.0, RHO, NU, ALL).force;
                fd.set_column(k, &((fp - fm) / (2.0 * h)));
            }
            worst = worst.max(rel_err(&exact[j], &fd));
        }
        worst
    }

    #[test]
    fn velocity_jacobian_matches_central_differences() {
        let ws = [
            V3::new(0.5, 0.1, -0.05),
            V3::new(-0.3, 0.4, 0.2),
            V3::new(0.05, -0.02, 0.6),
            V3::new(1.5, 0.9, -0.7),
        ];
        for model in models() {
            for w in ws {
                for zeta in [[1.0, 1.2, 0.4], [0.3, -0.1, 0.2]] {
                    let e = check_dfdw(model, w, zeta);
                    assert!(e < 1e-6, "{:?} w {w:?}: rel err {e}", model.id());
                }
            }
        }
    }

    #[test]
    fn position_jacobian_matches_central_differences() {
        let ws = [V3::new(0.5, 0.1, -0.05), V3::new(-0.3, 0.4, 0.2)];
        for model in models() {
            for w in ws {
                for zeta in [[1.0, 1.2, 0.4], [0.3, -0.1, 0.2], [0.3, -0.1, -0.2]] {
                    let e = check_dfdp(model, w, zeta);
                    assert!(e < 1e-6, "{:?} w {w:?} ζ {zeta:?}: rel err {e}", model.id());
                }
            }
        }
    }

    #[test]
    fn drag_part_is_symmetric_positive_definite() {
        let n = net(ScreenModel::Const { cd: 0.3, cl: 0.0 });
        let j = triangle(
            &n,
            tri(),
            [1.0; 3],
            V3::new(0.3, -0.2, 0.1),
            1.0,
            RHO,
            NU,
            ALL,
        )
        .dfdw;
        assert!(rel_err(&j, &j.transpose()) < 1e-14);
        assert!(j.symmetric_eigenvalues().iter().all(|e| *e > 0.0));
    }

    #[test]
    fn zero_speed_guard() {
        let l = triangle(
            &net(ScreenModel::S1),
            tri(),
            [1.0; 3],
            V3::zeros(),
            1.0,
            RHO,
            NU,
            ALL,
        );
        assert_eq!(l.force, V3::zeros());
        assert_eq!(l.dfdw, M3::zeros());
    }

    #[test]
    fn lift_zero_at_normal_incidence_for_singular_models() {
        // flow exactly along the normal: S5 and const have no defined lift direction
        let p = [
            V3::new(0.0, 0.0, -1.0),
            V3::new(0.0, 1.0, -1.0),
            V3::new(0.0, 0.0, -2.0),
        ];
        for model in [ScreenModel::S5, ScreenModel::Const { cd: 0.3, cl: 0.1 }] {
            let id = model.id();
            assert!(matches!(id, ScreenModelId::S5 | ScreenModelId::Const));
            let l = triangle(
                &net(model),
                p,
                [1.0; 3],
                V3::new(0.5, 0.0, 0.0),
                1.0,
                RHO,
                NU,
                ALL,
            );
            assert!(l.force.y.abs() < 1e-15 && l.force.z.abs() < 1e-15);
            assert!(l.dfdw.iter().all(|x| x.is_finite()));
        }
    }

    proptest! {
        #[test]
        fn random_states_jacobian(
            wx in -1.0f64..1.0, wy in -1.0f64..1.0, wz in -1.0f64..1.0, mi in 0usize..9,
        ) {
            let w = V3::new(wx, wy, wz);
            prop_assume!(w.norm() > 0.05);
            let model = models()[mi];
            let n0 = (tri()[1] - tri()[0]).cross(&(tri()[2] - tri()[0])).normalize();
            let c = n0.dot(&w).abs() / w.norm();
            // away from kinks: θ = 0 (S5/const), c = 0 (orientation flip)
            prop_assume!(c > 0.02 && c < 0.999);
            let e = check_dfdw(model, w, [1.0; 3]);
            prop_assert!(e < 1e-6, "{:?} err {}", model.id(), e);
        }

        #[test]
        fn drag_along_relative_velocity_lift_perpendicular(
            wx in -1.0f64..1.0, wy in -1.0f64..1.0, wz in -1.0f64..1.0,
        ) {
            let w = V3::new(wx, wy, wz);
            prop_assume!(w.norm() > 0.05);
            let n = net(ScreenModel::S1);
            let l = triangle(&n, tri(), [1.0; 3], w, 1.0, RHO, NU, Want::default());
            let a0 = 0.5 * (tri()[1] - tri()[0]).cross(&(tri()[2] - tri()[0]));
            let u = w.normalize();
            let th = (a0.normalize().dot(&u)).abs().acos();
            let (cd, cl) = ScreenModel::S1.cd_cl(th, 0.22, 1.0);
            let q = 0.5 * RHO * a0.norm() * w.norm_squared();
            prop_assert!((l.force.dot(&u) - q * cd).abs() < 1e-9 * q);
            let lift = l.force - l.force.dot(&u) * u;
            prop_assert!((lift.norm() - q * cl.abs()).abs() < 1e-9 * q);
            // lift lies in the (U, n) plane
            prop_assert!(lift.dot(&a0.cross(&u)).abs() < 1e-9 * q);
        }
    }
}
