//! Rotation-free bending hinge on three consecutive nodes: energy, internal force and the
//! exact 9×9 tangent (docs/theory/fem.md#bending).
//!
//! With e₁ = x_b − x_a, e₂ = x_c − x_b, t = cos φ = ê₁·ê₂ (φ the turning angle) and
//! q = tan²(φ/2) = |ê₁ − ê₂|²/|ê₁ + ê₂|², the discrete curvature is |κb| = 2√q (the norm of the
//! discrete-elastic-rod curvature binormal 2·e₁×e₂/(|e₁||e₂| + e₁·e₂)) and the energy is
//!
//! ```text
//! W = EI/(2ℓ̄)·(|κb| − κ̄)²
//! ```
//!
//! with κ̄ = |κb| and ℓ̄ = (|e₁| + |e₂|)/2 of the as-built geometry. W depends on t only, so
//! f = W'(t)·∇t and K = W''(t)·∇t∇tᵀ + W'(t)·∇²t.

/// Smallest tan²(φ/2) at which the curvature-magnitude term of a curved hinge is evaluated; below
/// it (φ < 2e-6 rad: a curved member's hinge pulled exactly straight) that term's force
/// direction is undefined and only its smooth part is kept (docs/theory/fem.md#bending).
const Q_MIN: f64 = 1e-12;

/// A bending hinge (resolved properties).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hinge {
    /// Nodes a, b (the hinge node), c.
    pub nodes: [usize; 3],
    /// Bending stiffness EI [N·m²].
    pub ei: f64,
    /// Voronoi length ℓ̄ = (|ē₁| + |ē₂|)/2 of the as-built edges [m].
    pub length: f64,
    /// Rest curvature κ̄ = 2·tan(φ̄/2) of the as-built turning angle φ̄ (dimensionless, ≥ 0;
    /// set to 0 below 1e-8, i.e. for a member built straight).
    pub rest_curvature: f64,
}

impl Hinge {
    /// Hinge with its rest state from the as-built positions; `None` if an edge has zero length
    /// or the edges fold back (φ̄ ≥ π − 1e-6).
    pub(crate) fn as_built(nodes: [usize; 3], ei: f64, x: [[f64; 3]; 3]) -> Option<Self> {
        let g = Geometry::new(x[0], x[1], x[2])?;
        let kappa = 2.0 * g.q.sqrt();
        Some(Self {
            nodes,
            ei,
            length: 0.5 * (g.n1 + g.n2),
            rest_curvature: if kappa < 1e-8 { 0.0 } else { kappa },
        })
    }
}

/// Result of evaluating one hinge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HingeEval {
    /// Bending energy W [J].
    pub energy: f64,
    /// Internal force ∂W/∂x per node (a, b, c), q sense [N].
    pub force: [[f64; 3]; 3],
    /// Tangent ∂²W/∂x² [N/m], rows/columns 3·node + component.
    pub k: [[f64; 9]; 9],
    /// Degenerate (zero edge, folded back) or non-finite.
    pub bad: bool,
}

impl Default for HingeEval {
    fn default() -> Self {
        Self {
            energy: 0.0,
            force: [[0.0; 3]; 3],
            k: [[0.0; 9]; 9],
            bad: false,
        }
    }
}

/// Edge geometry of a hinge.
struct Geometry {
    n1: f64,
    n2: f64,
    u1: [f64; 3],
    u2: [f64; 3],
    /// cos φ.
    t: f64,
    /// tan²(φ/2).
    q: f64,
}

impl Geometry {
    fn new(xa: [f64; 3], xb: [f64; 3], xc: [f64; 3]) -> Option<Self> {
        let e1 = sub(xb, xa);
        let e2 = sub(xc, xb);
        let (n1, n2) = (norm(e1), norm(e2));
        if !(n1 > 0.0 && n2 > 0.0 && n1.is_finite() && n2.is_finite()) {
            return None;
        }
        let u1 = e1.map(|c| c / n1);
        let u2 = e2.map(|c| c / n2);
        // 1 − t = |û₁ − û₂|²/2 and 1 + t = |û₁ + û₂|²/2 without cancellation.
        let dm = norm2(sub(u1, u2));
        let dp = norm2([u1[0] + u2[0], u1[1] + u2[1], u1[2] + u2[2]]);
        if dp < 1e-12 {
            return None;
        }
        Some(Self {
            n1,
            n2,
            u1,
            u2,
            t: 1.0 - 0.5 * dm,
            q: dm / dp,
        })
    }
}

/// W(t), W'(t), W''(t) of a hinge at q = tan²(φ/2), t = cos φ.
fn energy_of_t(h: &Hinge, q: f64, t: f64) -> (f64, f64, f64) {
    let c0 = 0.5 * h.ei / h.length;
    let op = 1.0 + t;
    let dq = -2.0 / (op * op);
    let ddq = 4.0 / (op * op * op);
    let kb = h.rest_curvature;
    // W = c0·(4q − 4κ̄√q + κ̄²): the smooth part and the curvature-magnitude (cone) part.
    let g = 2.0 * q.sqrt();
    let w = c0 * (g - kb) * (g - kb);
    let (mut w1, mut w2) = (4.0 * c0 * dq, 4.0 * c0 * ddq);
    if kb > 0.0 && q >= Q_MIN {
        let sq = q.sqrt();
        let g1 = dq / sq;
        let g2 = ddq / sq - 0.5 * dq * dq / (q * sq);
        w1 -= 2.0 * c0 * kb * g1;
        w2 -= 2.0 * c0 * kb * g2;
    }
    (w, w1, w2)
}

/// Bending energy W [J] of hinge `h` at positions (x_a, x_b, x_c); +∞ if degenerate.
#[cfg(test)]
pub(crate) fn energy(h: &Hinge, xa: [f64; 3], xb: [f64; 3], xc: [f64; 3]) -> f64 {
    match Geometry::new(xa, xb, xc) {
        Some(g) => energy_of_t(h, g.q, g.t).0,
        None => f64::INFINITY,
    }
}

/// Evaluates hinge `h` at (x_a, x_b, x_c) into `out`; the tangent only if `tangent`.
pub(crate) fn evaluate(
    h: &Hinge,
    xa: [f64; 3],
    xb: [f64; 3],
    xc: [f64; 3],
    tangent: bool,
    out: &mut HingeEval,
) {
    let Some(g) = Geometry::new(xa, xb, xc) else {
        out.bad = true;
        out.energy = f64::INFINITY;
        return;
    };
    out.bad = false;
    let (w, w1, w2) = energy_of_t(h, g.q, g.t);
    out.energy = w;
    let (u1, u2, t) = (g.u1, g.u2, g.t);
    // ∇t with respect to e₁ and e₂.
    let mut gt = [[0.0; 3]; 2];
    for k in 0..3 {
        gt[0][k] = (u2[k] - t * u1[k]) / g.n1;
        gt[1][k] = (u1[k] - t * u2[k]) / g.n2;
    }
    for k in 0..3 {
        out.force[0][k] = -w1 * gt[0][k];
        out.force[1][k] = w1 * (gt[0][k] - gt[1][k]);
        out.force[2][k] = w1 * gt[1][k];
    }
    out.bad = !(w.is_finite() && w1.is_finite());
    if !tangent {
        return;
    }
    // Edge Hessian H = W''·∇t∇tᵀ + W'·∇²t in 3×3 blocks H[p][q] (p, q ∈ {e₁, e₂}).
    let mut he = [[[[0.0; 3]; 3]; 2]; 2];
    let (i1, i2, i12) = (
        1.0 / (g.n1 * g.n1),
        1.0 / (g.n2 * g.n2),
        1.0 / (g.n1 * g.n2),
    );
    for i in 0..3 {
        for j in 0..3 {
            let d = if i == j { 1.0 } else { 0.0 };
            let sym = u2[i] * u1[j] + u1[i] * u2[j];
            let t11 = i1 * (-sym - t * d + 3.0 * t * u1[i] * u1[j]);
            let t22 = i2 * (-sym - t * d + 3.0 * t * u2[i] * u2[j]);
            let t12 = i12 * (d - u1[i] * u1[j] - u2[i] * u2[j] + t * u1[i] * u2[j]);
            he[0][0][i][j] = w2 * gt[0][i] * gt[0][j] + w1 * t11;
            he[1][1][i][j] = w2 * gt[1][i] * gt[1][j] + w1 * t22;
            he[0][1][i][j] = w2 * gt[0][i] * gt[1][j] + w1 * t12;
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            he[1][0][i][j] = he[0][1][j][i];
        }
    }
    // Nodes from edges: e₁ = x_b − x_a, e₂ = x_c − x_b; B[p][node].
    const B: [[f64; 3]; 2] = [[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]];
    for na in 0..3 {
        for nb in 0..3 {
            for i in 0..3 {
                for j in 0..3 {
                    let mut s = 0.0;
                    for (p, bp) in B.iter().enumerate() {
                        for (q, bq) in B.iter().enumerate() {
                            s += bp[na] * bq[nb] * he[p][q][i][j];
                        }
                    }
                    out.k[3 * na + i][3 * nb + j] = s;
                }
            }
        }
    }
    out.bad |= !w2.is_finite();
}

#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn norm2(a: [f64; 3]) -> f64 {
    a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
}

#[inline]
fn norm(a: [f64; 3]) -> f64 {
    norm2(a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn hinge(x: [[f64; 3]; 3], ei: f64) -> Hinge {
        Hinge::as_built([0, 1, 2], ei, x).unwrap()
    }

    /// Central-difference gradient and Hessian of the energy / force at `x`.
    fn check_fd(h: &Hinge, x: [[f64; 3]; 3]) -> std::result::Result<(), TestCaseError> {
        let mut ev = HingeEval::default();
        evaluate(h, x[0], x[1], x[2], true, &mut ev);
        prop_assert!(!ev.bad);
        let scale = h.ei / h.length;
        let step = 1e-6 * h.length;
        for c in 0..9 {
            let mut xp = x;
            let mut xm = x;
            xp[c / 3][c % 3] += step;
            xm[c / 3][c % 3] -= step;
            let dw =
                (energy(h, xp[0], xp[1], xp[2]) - energy(h, xm[0], xm[1], xm[2])) / (2.0 * step);
            let f = ev.force[c / 3][c % 3];
            prop_assert!(
                (dw - f).abs() < 1e-6 * (scale / h.length + f.abs()),
                "force dof {}: fd {} vs {}",
                c,
                dw,
                f
            );
            let mut ep = HingeEval::default();
            let mut em = HingeEval::default();
            evaluate(h, xp[0], xp[1], xp[2], false, &mut ep);
            evaluate(h, xm[0], xm[1], xm[2], false, &mut em);
            for r in 0..9 {
                let kfd = (ep.force[r / 3][r % 3] - em.force[r / 3][r % 3]) / (2.0 * step);
                let k = ev.k[r][c];
                prop_assert!(
                    (kfd - k).abs() < 1e-6 * (scale / (h.length * h.length) + k.abs()),
                    "k[{}][{}]: fd {} vs {}",
                    r,
                    c,
                    kfd,
                    k
                );
            }
        }
        Ok(())
    }

    proptest! {
        /// Force and tangent are the exact derivatives of the energy, for straight and curved
        /// rest states, over random current geometries (rel. 1e-6).
        #[test]
        fn force_and_tangent_match_finite_differences(
            r0 in prop::array::uniform3(prop::array::uniform3(-1.0f64..1.0)),
            d in prop::array::uniform3(prop::array::uniform3(-0.4f64..0.4)),
            ei in 0.1f64..1e4,
            straight in any::<bool>(),
        ) {
            let mut rest = [[0.0, 0.0, 0.0], [1.0, 0.1, -0.2], [1.7, 0.9, 0.3]];
            for (p, o) in rest.iter_mut().zip(&r0) {
                for k in 0..3 { p[k] += 0.3 * o[k]; }
            }
            if straight {
                rest = [[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [2.0, 1.0, 0.0]];
            }
            let h = hinge(rest, ei);
            let mut x = rest;
            for (p, o) in x.iter_mut().zip(&d) {
                for k in 0..3 { p[k] += o[k]; }
            }
            let g = Geometry::new(x[0], x[1], x[2]);
            // Away from folding back and from the cone tip of a curved hinge.
            prop_assume!(g.is_some_and(|g| g.t > -0.8 && (straight || g.q > 1e-4)
                && g.n1 > 0.2 && g.n2 > 0.2));
            check_fd(&h, x)?;
        }
    }

    #[test]
    fn rest_state_is_force_free_and_rigid_motion_too() {
        let x = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [1.8, 0.9, 0.1]];
        let h = hinge(x, 7.0);
        assert!(h.rest_curvature > 0.0);
        // A large rigid rotation (about an oblique axis) and a translation.
        let (s, c) = (1.3f64.sin(), 1.3f64.cos());
        let rot = |p: [f64; 3]| [c * p[0] - s * p[2] + 4.0, p[1] - 2.0, s * p[0] + c * p[2]];
        for y in [x, x.map(rot)] {
            let mut ev = HingeEval::default();
            evaluate(&h, y[0], y[1], y[2], true, &mut ev);
            assert!(ev.energy < 1e-24, "energy {}", ev.energy);
            for f in ev.force {
                for k in f {
                    assert!(k.abs() < 1e-10, "force {k}");
                }
            }
        }
    }

    #[test]
    fn small_angle_energy_is_half_ei_kappa_squared_times_length() {
        // Straight rest, edges of 0.5 m, turning angle φ: W ≈ ½·EI·(φ/ℓ)²·ℓ.
        let h = hinge([[0.0; 3], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]], 3.0);
        let phi = 1e-3f64;
        let w = energy(
            &h,
            [0.0; 3],
            [0.5, 0.0, 0.0],
            [0.5 + 0.5 * phi.cos(), 0.5 * phi.sin(), 0.0],
        );
        let expect = 0.5 * 3.0 * (phi / 0.5) * (phi / 0.5) * 0.5;
        assert!((w / expect - 1.0).abs() < 1e-6, "{w} vs {expect}");
        assert!(Hinge::as_built([0, 1, 2], 1.0, [[0.0; 3], [0.0; 3], [1.0; 3]]).is_none());
    }
}
