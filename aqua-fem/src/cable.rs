//! The 2-node cable element: axial force, tangent blocks, strain energy
//! (docs/theory/fem.md#cable-element).

use crate::model::Cable;

/// Result of evaluating one cable element at a state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct CableEval {
    /// Axial force T [N] (signed, incl. damping).
    pub tension: f64,
    /// Engineering strain ε.
    pub strain: f64,
    /// Strain rate ε̇ [1/s].
    pub strain_rate: f64,
    /// Current length l [m].
    pub length: f64,
    /// Switch s (1 taut, r_c slack).
    pub switch: f64,
    /// Internal force on node b (= −force on node a) [N]: T·e.
    pub force_b: [f64; 3],
    /// ∂(force_b)/∂x_b [N/m], row-major.
    pub k: [[f64; 3]; 3],
    /// ∂(force_b)/∂v_b [N·s/m], row-major.
    pub c: [[f64; 3]; 3],
    /// Set when the element is degenerate (l < 1e-9·L0) or non-finite.
    pub bad: bool,
}

/// Evaluates element `e` with node positions/velocities. `damping` enables axial damping
/// (off in statics); `extra_ca` adds a damping coefficient [N·s] (stiffness-proportional
/// Rayleigh damping a_K·EA); `clamp_geometric` uses max(T, 0) in the geometric stiffness of
/// slack elements (s < 1).
#[inline]
pub(crate) fn evaluate(
    e: &Cable,
    xa: [f64; 3],
    xb: [f64; 3],
    va: [f64; 3],
    vb: [f64; 3],
    damping: bool,
    extra_ca: f64,
    clamp_geometric: bool,
) -> CableEval {
    let dx = [xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]];
    let l = (dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]).sqrt();
    let mut out = CableEval {
        length: l,
        ..Default::default()
    };
    if !(l.is_finite() && l >= 1e-9 * e.l0) {
        out.bad = true;
        return out;
    }
    let u = [dx[0] / l, dx[1] / l, dx[2] / l];
    let eps = (l - e.l0) / e.l0;
    let s = if eps > 0.0 { 1.0 } else { e.rc };
    let ca = if damping { e.ca + extra_ca } else { 0.0 };
    let (eps_dot, pdv) = if ca > 0.0 {
        let dv = [vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]];
        let ed = u[0] * dv[0] + u[1] * dv[1] + u[2] * dv[2];
        (
            ed / e.l0,
            [dv[0] - ed * u[0], dv[1] - ed * u[1], dv[2] - ed * u[2]],
        )
    } else {
        (0.0, [0.0; 3])
    };
    let t = s * (e.ea * eps + ca * eps_dot);
    let km = s * e.ea / e.l0;
    let kg = if clamp_geometric && s < 1.0 {
        t.max(0.0) / l
    } else {
        t / l
    };
    let cm = s * ca / e.l0;
    let kd = s * ca / (e.l0 * l);
    for i in 0..3 {
        for j in 0..3 {
            let p = if i == j { 1.0 } else { 0.0 } - u[i] * u[j];
            out.k[i][j] = km * u[i] * u[j] + kg * p + kd * u[i] * pdv[j];
            out.c[i][j] = cm * u[i] * u[j];
        }
    }
    out.tension = t;
    out.strain = eps;
    out.strain_rate = eps_dot;
    out.switch = s;
    out.force_b = [t * u[0], t * u[1], t * u[2]];
    out.bad = !t.is_finite();
    out
}

/// Strain energy ½·s·EA·ε²·L0 [J].
#[inline]
pub(crate) fn strain_energy(e: &Cable, strain: f64) -> f64 {
    let s = if strain > 0.0 { 1.0 } else { e.rc };
    0.5 * s * e.ea * strain * strain * e.l0
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn cable(ca: f64) -> Cable {
        Cable {
            a: 0,
            b: 1,
            l0: 1.3,
            ea: 2e4,
            rc: 1e-2,
            ca,
            mu: 1.0,
            group: 0,
            contact_diameter: 0.0,
        }
    }

    proptest! {
        /// The tangent blocks are the exact derivatives of the nodal force (central differences).
        #[test]
        fn tangent_matches_finite_differences(
            dx in prop::array::uniform3(-2.0f64..2.0),
            vb in prop::array::uniform3(-1.0f64..1.0),
            ca in 0.0f64..50.0,
        ) {
            let l = (dx[0]*dx[0] + dx[1]*dx[1] + dx[2]*dx[2]).sqrt();
            prop_assume!(l > 0.2 && (l - 1.3).abs() > 1e-3);
            let e = cable(ca);
            let xa = [0.1, -0.2, 0.3];
            let xb = [xa[0] + dx[0], xa[1] + dx[1], xa[2] + dx[2]];
            let va = [0.0; 3];
            let ev = evaluate(&e, xa, xb, va, vb, true, 0.0, false);
            let h = 1e-6;
            for j in 0..3 {
                let mut xp = xb; xp[j] += h;
                let mut xm = xb; xm[j] -= h;
                let fp = evaluate(&e, xa, xp, va, vb, true, 0.0, false).force_b;
                let fm = evaluate(&e, xa, xm, va, vb, true, 0.0, false).force_b;
                let mut vp = vb; vp[j] += h;
                let mut vm = vb; vm[j] -= h;
                let gp = evaluate(&e, xa, xb, va, vp, true, 0.0, false).force_b;
                let gm = evaluate(&e, xa, xb, va, vm, true, 0.0, false).force_b;
                for i in 0..3 {
                    let kfd = (fp[i] - fm[i]) / (2.0 * h);
                    let cfd = (gp[i] - gm[i]) / (2.0 * h);
                    let scale = 1.0 + ev.k[i][j].abs() + e.ea / e.l0 * 1e-6;
                    prop_assert!((kfd - ev.k[i][j]).abs() < 1e-5 * scale,
                        "k[{}][{}] fd {} vs {}", i, j, kfd, ev.k[i][j]);
                    prop_assert!((cfd - ev.c[i][j]).abs() < 1e-5 * (1.0 + ev.c[i][j].abs()));
                }
            }
        }
    }

    #[test]
    fn slack_switch_and_energy() {
        let e = cable(0.0);
        let ev = evaluate(
            &e,
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0; 3],
            [0.0; 3],
            false,
            0.0,
            false,
        );
        assert_eq!(ev.switch, 1e-2);
        assert!(ev.tension < 0.0);
        let ev = evaluate(
            &e,
            [0.0; 3],
            [1.43, 0.0, 0.0],
            [0.0; 3],
            [0.0; 3],
            false,
            0.0,
            false,
        );
        assert!((ev.tension - 2e4 * 0.1).abs() < 1e-9);
        assert!((strain_energy(&e, 0.1) - 0.5 * 2e4 * 0.01 * 1.3).abs() < 1e-9);
        assert!(
            evaluate(
                &e, [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], false, 0.0, false
            )
            .bad
        );
    }
}
