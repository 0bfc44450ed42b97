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
    /// The damping part of T [N]: T − s·EA·ε (dissipative: its power is ≥ 0).
    pub damping_force: f64,
    /// Internal force on node b (= −force on node a) [N]: T·e.
    pub force_b: [f64; 3],
    /// ∂(force_b)/∂x_b [N/m], row-major.
    pub k: [[f64; 3]; 3],
    /// ∂(force_b)/∂v_b [N·s/m], row-major.
    pub c: [[f64; 3]; 3],
    /// Set when the element is degenerate (l < 1e-9·L0) or non-finite.
    pub bad: bool,
    /// Unit vector from node a to node b.
    pub force_b_dir: [f64; 3],
}

/// Strain over which the damping of a tension-only element ramps in from r_c·c_a to c_a
/// (docs/theory/fem.md#slack-members).
pub const DAMPING_RAMP_STRAIN: f64 = 1e-5;

/// The axial force T [N] and its derivatives ∂T/∂ε [N] and ∂T/∂ε̇ [N·s] of an element with
/// compression ratio r_c, stiffness EA [N] and damping c_a [N·s] at strain ε and strain rate ε̇
/// (docs/theory/fem.md#slack-members). Slack (ε ≤ 0): T = r_c·(EA·ε + c_a·ε̇). Taut:
///
/// ```text
/// T = EA·ε + d(ε)·c_a·ε̇,   d(ε) = r_c + (1 − r_c)·min(1, ε/ε_d)
/// ```
///
/// with ε_d = [`DAMPING_RAMP_STRAIN`], so T is continuous through ε = 0 while stretching (it
/// jumped by (1 − r_c)·c_a·ε̇ before). Members with r_c ≥ 1 (bars) are plain Kelvin–Voigt.
#[inline]
pub(crate) fn axial_force(rc: f64, ea: f64, ca: f64, eps: f64, eps_dot: f64) -> (f64, f64, f64) {
    if rc >= 1.0 || eps >= DAMPING_RAMP_STRAIN {
        return (ea * eps + ca * eps_dot, ea, ca);
    }
    if eps <= 0.0 {
        return (rc * (ea * eps + ca * eps_dot), rc * ea, rc * ca);
    }
    let d = rc + (1.0 - rc) * eps / DAMPING_RAMP_STRAIN;
    let dd = (1.0 - rc) / DAMPING_RAMP_STRAIN;
    (ea * eps + d * ca * eps_dot, ea + dd * ca * eps_dot, d * ca)
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
    out.force_b_dir = u;
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
    let (t, dt_deps, dt_deps_dot) = axial_force(e.rc, e.ea, ca, eps, eps_dot);
    let km = dt_deps / e.l0;
    let kg = if clamp_geometric && s < 1.0 {
        t.max(0.0) / l
    } else {
        t / l
    };
    let cm = dt_deps_dot / e.l0;
    let kd = dt_deps_dot / (e.l0 * l);
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
    out.damping_force = t - s * e.ea * eps;
    out.force_b = [t * u[0], t * u[1], t * u[2]];
    out.bad = !t.is_finite();
    out
}

/// Strain energy ½·s·EA·ε²·L0 [J].
#[inline]
/// Strain energy W(l) [J] of element `e` at length l.
pub(crate) fn energy_at_length(e: &Cable, l: f64) -> f64 {
    strain_energy(e, (l - e.l0) / e.l0)
}

/// Replaces the elastic part of the axial force of `out` (evaluated at the midpoint of a
/// step, length l_m, direction u_m) by the discrete gradient of the strain energy between the
/// step's start length l0 and end vector d1 (length l1, direction u1)
/// (docs/theory/fem.md#energy-consistent-midpoint):
///
/// ```text
/// T_alg = 2·l_m·(W(l1) − W(l0)) / (l1² − l0²)
/// ```
///
/// so that the work of the element's forces over the step, T_alg/l_m·d_m·Δd = T_alg·Δ(l²)/(2·l_m),
/// equals W(l1) − W(l0) exactly. The tangent `k` becomes 2·∂f_b/∂x1_b (the midpoint rule
/// assembles ½·k): u_m ⊗ (2·∂T_alg/∂l1·u1 + T_alg/l_m·u_m) + (T/l_m)(I − u_m⊗u_m), with
/// ∂T_alg/∂l1 = (2·l_m/Δq)·(T(l1) − l1·T_alg/l_m), Δq = l1² − l0². The damping part stays the
/// midpoint's.
#[inline]
pub(crate) fn use_secant_tension(e: &Cable, l0: f64, d1: [f64; 3], out: &mut CableEval) {
    if out.bad {
        return;
    }
    let l1 = (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]).sqrt();
    if !(l1 > 1e-9 * e.l0) {
        return;
    }
    let lm = out.length;
    let u = out.force_b_dir;
    let u1 = [d1[0] / l1, d1[1] / l1, d1[2] / l1];
    let tension_at = |l: f64| {
        let eps = (l - e.l0) / e.l0;
        let s = if eps > 0.0 { 1.0 } else { e.rc };
        s * e.ea * eps
    };
    let dq = l1 * l1 - l0 * l0;
    let (t_alg, dt_dl1) = if dq.abs() > 1e-8 * lm * lm {
        let t = 2.0 * lm * (energy_at_length(e, l1) - energy_at_length(e, l0)) / dq;
        (t, 2.0 * lm / dq * (tension_at(l1) - l1 * t / lm))
    } else {
        // The limit: W'(l̄)·l_m/l̄ at l̄² = (l0² + l1²)/2, l̄ moving by ½·dl1.
        let lb = (0.5 * (l0 * l0 + l1 * l1)).sqrt();
        let s = if lb > e.l0 { 1.0 } else { e.rc };
        (tension_at(lb) * lm / lb, 0.5 * s * e.ea / e.l0 * lm / lb)
    };
    let km = out.switch * e.ea / e.l0;
    let d = t_alg - out.switch * e.ea * out.strain;
    out.tension += d;
    for i in 0..3 {
        out.force_b[i] += d * u[i];
        for j in 0..3 {
            let p = if i == j { 1.0 } else { 0.0 } - u[i] * u[j];
            out.k[i][j] +=
                -km * u[i] * u[j] + u[i] * (2.0 * dt_dl1 * u1[j] + t_alg / lm * u[j]) + d / lm * p;
        }
    }
}

/// The elastic axial force W′(l) = s·EA·ε [N] of element `e` at length l (no damping).
#[inline]
pub(crate) fn elastic_tension(e: &Cable, l: f64) -> f64 {
    let eps = (l - e.l0) / e.l0;
    let s = if eps > 0.0 { 1.0 } else { e.rc };
    s * e.ea * eps
}

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

    /// The ramped damping of a tension-only element (r_c = 0): continuous through ε = 0 while
    /// stretching (it jumped by c_a·ε̇ before), half the damping force halfway up the ramp, full
    /// Kelvin–Voigt beyond it, and the tangent inside the ramp the derivative of the force
    /// (central differences).
    #[test]
    fn axial_damping_ramps_in_continuously_with_its_tangent() {
        let e = Cable {
            rc: 0.0,
            ..cable(40.0)
        };
        let (xa, va, vb) = ([0.0; 3], [0.0; 3], [0.3, 0.1, 0.0]);
        let force = |l: f64| evaluate(&e, xa, [l, 0.0, 0.0], va, vb, true, 0.0, false).tension;
        let ca_edot = 40.0 * 0.3 / 1.3;
        assert!(force(1.3 * (1.0 + 1e-14)).abs() < 1e-6 * ca_edot);
        let beyond = 1.3 * (1.0 + 2.0 * DAMPING_RAMP_STRAIN);
        let full = 2e4 * 2.0 * DAMPING_RAMP_STRAIN + ca_edot;
        assert!((force(beyond) - full).abs() < 1e-9 * full);
        let half = 1.3 * (1.0 + 0.5 * DAMPING_RAMP_STRAIN);
        let expected = 2e4 * 0.5 * DAMPING_RAMP_STRAIN + 0.5 * ca_edot;
        assert!((force(half) - expected).abs() < 1e-6 * expected);
        let n = (1.0f64 + 0.02 * 0.02 + 0.01 * 0.01).sqrt();
        let xb = [half / n, 0.02 * half / n, -0.01 * half / n];
        let ev = evaluate(&e, xa, xb, va, vb, true, 0.0, false);
        assert!((ev.strain / DAMPING_RAMP_STRAIN - 0.5).abs() < 1e-6);
        assert!(ev.damping_force * ev.strain_rate >= 0.0);
        let h = 1e-10;
        for j in 0..3 {
            let (mut xp, mut xm) = (xb, xb);
            xp[j] += h;
            xm[j] -= h;
            let fp = evaluate(&e, xa, xp, va, vb, true, 0.0, false).force_b;
            let fm = evaluate(&e, xa, xm, va, vb, true, 0.0, false).force_b;
            for i in 0..3 {
                let kfd = (fp[i] - fm[i]) / (2.0 * h);
                assert!(
                    (kfd - ev.k[i][j]).abs() < 1e-3 * (1.0 + ev.k[i][j].abs()),
                    "k[{i}][{j}] fd {kfd} vs {}",
                    ev.k[i][j]
                );
            }
        }
    }
}
