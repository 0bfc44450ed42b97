//! The screen of a net triangle (docs/theory/hydrodynamics.md#net-triangle-screen): its solidity
//! follows its twines.
//!
//! Inside a triangle with mesh coordinates (U_k, V_k) at its corners the twine vectors are
//! u = ∂x/∂U = Σ a_k x_k and v = ∂x/∂V = Σ b_k x_k (a_k, b_k the gradients of the linear shape
//! functions in (U, V)). One mesh cell, the parallelogram of u and v, holds one U bar and one V
//! bar of diameter d, crossing once, so the solidity is
//!
//!   Sn = (d·|u| + d·|v| − d²) / |u × v|,
//!
//! 2d/l_p − (d/l_p)² for square meshes open at 90°, growing as the meshes close. The load's
//! position Jacobian carries ∂Sn/∂x through [`TwineMap::solidity_gradient`].

use crate::types::V3;

/// Largest solidity a closing net triangle is given (the screen models' data end well below).
pub const MAX_TRIANGLE_SOLIDITY: f64 = 0.95;

/// The twine map of a net triangle: u = Σ a_k x_k, v = Σ b_k x_k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwineMap {
    /// ∂N_k/∂U [1/half mesh].
    pub a: [f64; 3],
    /// ∂N_k/∂V [1/half mesh].
    pub b: [f64; 3],
}

impl TwineMap {
    /// The map of a triangle with corner mesh coordinates `uv`; `None` when the (U, V)
    /// triangle has no area.
    pub fn new(uv: [[f64; 2]; 3]) -> Option<Self> {
        let (u1, v1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
        let (u2, v2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
        let det = u1 * v2 - u2 * v1;
        if !(det.abs() > 0.0 && det.is_finite()) {
            return None;
        }
        // ∇N_1 = (v2, −u2)/det, ∇N_2 = (−v1, u1)/det, ∇N_0 = −∇N_1 − ∇N_2.
        let a1 = v2 / det;
        let b1 = -u2 / det;
        let a2 = -v1 / det;
        let b2 = u1 / det;
        Some(Self {
            a: [-a1 - a2, a1, a2],
            b: [-b1 - b2, b1, b2],
        })
    }

    /// The twine vectors (u, v) [m per half mesh] at corner positions `p`.
    pub fn twines(&self, p: &[V3; 3]) -> (V3, V3) {
        let u = p[0] * self.a[0] + p[1] * self.a[1] + p[2] * self.a[2];
        let v = p[0] * self.b[0] + p[1] * self.b[1] + p[2] * self.b[2];
        (u, v)
    }

    /// Solidity of the triangle at positions `p` for twine diameter `d` [m], capped at
    /// [`MAX_TRIANGLE_SOLIDITY`].
    pub fn solidity(&self, p: &[V3; 3], d: f64) -> f64 {
        let (u, v) = self.twines(p);
        solidity(&u, &v, d)
    }

    /// Solidity (as [`Self::solidity`]) and its gradients ∂Sn/∂x_k [1/m] with respect to the
    /// corner positions (zero where the cap holds):
    /// ∂Sn/∂x_k = [d·(a_k·û + b_k·v̂) − Sn·(a_k·(v × ŵ) + b_k·(ŵ × u))]/|w|, w = u × v.
    pub fn solidity_gradient(&self, p: &[V3; 3], d: f64) -> (f64, [V3; 3]) {
        let (u, v) = self.twines(p);
        let sn = solidity(&u, &v, d);
        let w = u.cross(&v);
        let wn = w.norm();
        let (un, vn) = (u.norm(), v.norm());
        if sn >= MAX_TRIANGLE_SOLIDITY || sn <= 0.0 || wn <= 0.0 || un <= 0.0 || vn <= 0.0 {
            return (sn, [V3::zeros(); 3]);
        }
        let (uh, vh, wh) = (u / un, v / vn, w / wn);
        let (dw_du, dw_dv) = (v.cross(&wh), wh.cross(&u));
        let grad = std::array::from_fn(|k| {
            (d * (self.a[k] * uh + self.b[k] * vh) - sn * (self.a[k] * dw_du + self.b[k] * dw_dv))
                / wn
        });
        (sn, grad)
    }

    /// The opening angle between the U and V twines [rad], in [0, π].
    pub fn opening_angle(&self, p: &[V3; 3]) -> f64 {
        let (u, v) = self.twines(p);
        u.angle(&v)
    }
}

/// Solidity of a mesh cell of twine vectors `u`, `v` [m] and twine diameter `d` [m], capped at
/// [`MAX_TRIANGLE_SOLIDITY`].
pub fn solidity(u: &V3, v: &V3, d: f64) -> f64 {
    let cell = u.cross(v).norm();
    let covered = d * (u.norm() + v.norm()) - d * d;
    if cell <= covered / MAX_TRIANGLE_SOLIDITY {
        MAX_TRIANGLE_SOLIDITY
    } else {
        (covered / cell).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_mesh_gives_the_formula_and_closing_meshes_more() {
        let (d, lp) = (2e-3, 20e-3);
        // A triangle of 3 × 2 half meshes, open at 90°.
        let uv = [[0.0, 0.0], [3.0, 0.0], [0.0, 2.0]];
        let t = TwineMap::new(uv).unwrap();
        let p = uv.map(|q| V3::new(q[0] * lp, q[1] * lp, 0.0));
        let sn = t.solidity(&p, d);
        assert!(
            (sn - (2.0 * d / lp - (d / lp).powi(2))).abs() < 1e-14,
            "{sn}"
        );
        // Meshes closed to opening angle 2α: cell l²·sin 2α, twine 2dl − d².
        let alpha: f64 = 0.3;
        let (du, dv) = (
            V3::new(alpha.cos(), alpha.sin(), 0.0) * lp,
            V3::new(alpha.cos(), -alpha.sin(), 0.0) * lp,
        );
        let q = uv.map(|c| du * c[0] + dv * c[1]);
        let expect = (2.0 * d * lp - d * d) / (lp * lp * (2.0 * alpha).sin());
        assert!((t.solidity(&q, d) - expect).abs() < 1e-12);
        assert!((t.opening_angle(&q) - 2.0 * alpha).abs() < 1e-12);
        // Fully closed: capped.
        let flat = uv.map(|c| du * (c[0] + c[1]));
        assert_eq!(t.solidity(&flat, d), MAX_TRIANGLE_SOLIDITY);
        assert!(TwineMap::new([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_none());
    }

    #[test]
    fn solidity_gradient_is_the_derivative() {
        let (d, lp) = (2e-3, 20e-3);
        let t = TwineMap::new([[0.0, 0.0], [3.0, 0.5], [0.4, 2.0]]).unwrap();
        let p = [
            V3::new(0.0, 0.01, -0.02),
            V3::new(0.05, 0.0, 0.03) * lp / 0.02,
            V3::new(0.01, 0.04, 0.0) * lp / 0.02,
        ];
        let (_, g) = t.solidity_gradient(&p, d);
        let h = 1e-7;
        for k in 0..3 {
            for c in 0..3 {
                let (mut pp, mut pm) = (p, p);
                pp[k][c] += h;
                pm[k][c] -= h;
                let fd = (t.solidity(&pp, d) - t.solidity(&pm, d)) / (2.0 * h);
                assert!(
                    (g[k][c] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{k} {c}: {} vs {fd}",
                    g[k][c]
                );
            }
        }
    }
}
