//! Priour's triangular net element: a triangle of netting whose corners carry mesh coordinates
//! (U, V), with the twine vectors u = ∂x/∂U, v = ∂x/∂V of the linear map from (U, V) to space
//! and A_uv twines of each family, each a tension-only bar of rest length l_p
//! (docs/theory/fem.md#net-triangle). Each family is a cable element between 0 and u (resp.
//! v), so the axial law, its tangent, its damping and its discrete gradient are the cable's
//! (`cable.rs`).

use crate::cable::{self, CableEval};
use crate::error::{Result, invalid};
use crate::model::{AxialDamping, Cable, DEFAULT_COMPRESSION_RATIO};

/// Section of a net made of triangles: one twine's properties and the bar length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetTriangleSection {
    /// Axial stiffness EA of one twine [N] (> 0).
    pub ea: f64,
    /// Unstretched length l_p of a mesh bar (half a mesh: knot to knot) [m] (> 0).
    pub bar_length: f64,
    /// Mass per unstretched length μ of one twine [kg/m] (> 0).
    pub mass_per_length: f64,
    /// Compression ratio r_c ∈ [0, 1] of the twines (default 0: tension-only,
    /// docs/theory/fem.md#slack-members).
    pub compression_ratio: f64,
    /// Axial damping of one twine (the cable's law; `Ratio(ζ)` gives c_a = ζ·l_p·√(EA·μ)).
    pub axial_damping: AxialDamping,
}

impl NetTriangleSection {
    /// Section with EA [N] and μ [kg/m] of one twine and bar length l_p [m]; tension-only
    /// (r_c = [`DEFAULT_COMPRESSION_RATIO`]), no axial damping.
    pub fn new(ea: f64, bar_length: f64, mass_per_length: f64) -> Self {
        Self {
            ea,
            bar_length,
            mass_per_length,
            compression_ratio: DEFAULT_COMPRESSION_RATIO,
            axial_damping: AxialDamping::None,
        }
    }

    /// Sets the compression ratio r_c.
    pub fn with_compression_ratio(mut self, rc: f64) -> Self {
        self.compression_ratio = rc;
        self
    }

    /// Sets the axial damping of one twine.
    pub fn with_axial_damping(mut self, d: AxialDamping) -> Self {
        self.axial_damping = d;
        self
    }

    pub(crate) fn validate(&self, group: &str) -> Result<()> {
        for (key, v) in [
            ("ea [N]", self.ea),
            ("bar_length [m]", self.bar_length),
            ("mass_per_length [kg/m]", self.mass_per_length),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(
                    format!("net triangle group '{group}' {key}"),
                    v,
                    "> 0",
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.compression_ratio) {
            return Err(invalid(
                format!("net triangle group '{group}' compression_ratio"),
                self.compression_ratio,
                "0 <= r_c <= 1",
            ));
        }
        let (key, c) = match self.axial_damping {
            AxialDamping::None => return Ok(()),
            AxialDamping::Coefficient(c) => ("axial_damping [N s]", c),
            AxialDamping::Ratio(z) => ("axial_damping_ratio", z),
        };
        if !(c.is_finite() && c >= 0.0) {
            return Err(invalid(
                format!("net triangle group '{group}' {key}"),
                c,
                ">= 0",
            ));
        }
        Ok(())
    }

    /// The twine as a cable element of rest length l_p (its nodes are placeholders).
    pub(crate) fn twine(&self, group: usize) -> Cable {
        let (ea, mu, l0) = (self.ea, self.mass_per_length, self.bar_length);
        let ca = match self.axial_damping {
            AxialDamping::None => 0.0,
            AxialDamping::Coefficient(c) => c,
            AxialDamping::Ratio(z) => z * l0 * (ea * mu).sqrt(),
        };
        Cable {
            a: 0,
            b: 1,
            l0,
            ea,
            rc: self.compression_ratio,
            ca,
            mu,
            group,
            contact_diameter: 0.0,
        }
    }
}

/// A named group of net triangles sharing a section.
#[derive(Debug, Clone, PartialEq)]
pub struct NetTriangleGroup {
    /// Name.
    pub name: String,
    /// Section.
    pub section: NetTriangleSection,
    /// Triangles of the group.
    pub triangles: Vec<usize>,
}

/// Handle of a net triangle group.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NetGroupId(pub usize);

/// A triangle of netting (docs/theory/fem.md#net-triangle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetTriangle {
    /// Its three nodes.
    pub nodes: [usize; 3],
    /// Mesh coordinates (U, V) of each node: mesh bars along the two twine directions from
    /// an origin [-].
    pub uv: [[f64; 2]; 3],
    /// Group index.
    pub group: usize,
    /// a_k = ∂N_k/∂U: u = Σ a_k·x_k [1].
    pub(crate) grad_u: [f64; 3],
    /// b_k = ∂N_k/∂V: v = Σ b_k·x_k [1].
    pub(crate) grad_v: [f64; 3],
    /// A_uv = |area in (U, V)|: the number of U twines (and of V twines) in the triangle [-].
    pub(crate) area_uv: f64,
    /// One twine as a cable element from 0 to u (or v).
    pub(crate) twine: Cable,
}

/// The twines of a net triangle at a state (per single twine; static law, no damping).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetTriangleTwines {
    /// U twine vector u = ∂x/∂U: one stretched bar along U [m].
    pub u: [f64; 3],
    /// V twine vector v = ∂x/∂V [m].
    pub v: [f64; 3],
    /// Axial force of one U twine [N] (s·EA·ε, 0 when slack and tension-only).
    pub tension_u: f64,
    /// Axial force of one V twine [N].
    pub tension_v: f64,
    /// Angle between u and v [rad] (π/2 for an open square mesh).
    pub opening_angle: f64,
}

#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn combine(w: [f64; 3], p: [[f64; 3]; 3]) -> [f64; 3] {
    std::array::from_fn(|k| w[0] * p[0][k] + w[1] * p[1][k] + w[2] * p[2][k])
}

impl NetTriangle {
    /// The triangle on `nodes` with mesh coordinates `uv` in group `group` of `section`;
    /// `None` when the (U, V) triangle is degenerate (|A_uv| ≤ 1e-12·(longest side)²) or not
    /// finite.
    pub(crate) fn new(
        nodes: [usize; 3],
        uv: [[f64; 2]; 3],
        group: usize,
        section: &NetTriangleSection,
    ) -> Option<Self> {
        let [p1, p2, p3] = uv;
        let two_a = (p2[0] - p1[0]) * (p3[1] - p1[1]) - (p3[0] - p1[0]) * (p2[1] - p1[1]);
        let side2 = (0..3)
            .map(|k| {
                let (p, q) = (uv[k], uv[(k + 1) % 3]);
                (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)
            })
            .fold(0.0, f64::max);
        if !(two_a.is_finite() && side2.is_finite() && two_a.abs() > 2e-12 * side2) {
            return None;
        }
        // Gradients of the linear shape functions in (U, V): ∂N_k/∂U = (V_{k+1} − V_{k+2})/2A,
        // ∂N_k/∂V = (U_{k+2} − U_{k+1})/2A (signed A: either orientation).
        let grad_u = std::array::from_fn(|k| (uv[(k + 1) % 3][1] - uv[(k + 2) % 3][1]) / two_a);
        let grad_v = std::array::from_fn(|k| (uv[(k + 2) % 3][0] - uv[(k + 1) % 3][0]) / two_a);
        Some(Self {
            nodes,
            uv,
            group,
            grad_u,
            grad_v,
            area_uv: 0.5 * two_a.abs(),
            twine: section.twine(group),
        })
    }

    /// Signed area of the (U, V) triangle of `uv` (counter-clockwise positive) [-].
    pub fn signed_uv_area(uv: [[f64; 2]; 3]) -> f64 {
        let [p1, p2, p3] = uv;
        0.5 * ((p2[0] - p1[0]) * (p3[1] - p1[1]) - (p3[0] - p1[0]) * (p2[1] - p1[1]))
    }

    /// A_uv: the triangle's area in (U, V), the number of U twines (and of V twines) it holds.
    pub fn uv_area(&self) -> f64 {
        self.area_uv
    }

    /// The shape-function gradients (a_k, b_k): u = Σ a_k·x_k, v = Σ b_k·x_k.
    pub fn shape_gradients(&self) -> ([f64; 3], [f64; 3]) {
        (self.grad_u, self.grad_v)
    }

    /// Unstretched bar length l_p [m].
    pub fn bar_length(&self) -> f64 {
        self.twine.l0
    }

    /// Twine mass of the triangle, A_uv·2·l_p·μ [kg].
    pub fn mass(&self) -> f64 {
        2.0 * self.area_uv * self.twine.l0 * self.twine.mu
    }

    /// The node positions of the triangle from all node positions.
    #[inline]
    fn corners(&self, x: &[[f64; 3]]) -> [[f64; 3]; 3] {
        [x[self.nodes[0]], x[self.nodes[1]], x[self.nodes[2]]]
    }

    /// Twine vectors (u, v) = (∂x/∂U, ∂x/∂V) [m] at node positions `x` (all nodes).
    #[inline]
    pub fn twine_vectors(&self, x: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
        let p = self.corners(x);
        (combine(self.grad_u, p), combine(self.grad_v, p))
    }

    /// The twines at node positions `x` (all nodes): vectors, tension per twine (static law
    /// s·EA·ε, no damping) and opening angle.
    pub fn twines(&self, x: &[[f64; 3]]) -> NetTriangleTwines {
        let (u, v) = self.twine_vectors(x);
        let tension = |d: [f64; 3]| {
            let eps = (dot(d, d).sqrt() - self.twine.l0) / self.twine.l0;
            let s = if eps > 0.0 { 1.0 } else { self.twine.rc };
            s * self.twine.ea * eps
        };
        let c = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        NetTriangleTwines {
            u,
            v,
            tension_u: tension(u),
            tension_v: tension(v),
            opening_angle: dot(c, c).sqrt().atan2(dot(u, v)),
        }
    }

    /// Strain energy A_uv·(W(|u|) + W(|v|)) [J] at node positions `x`.
    pub fn strain_energy(&self, x: &[[f64; 3]]) -> f64 {
        let (u, v) = self.twine_vectors(x);
        let w = |d: [f64; 3]| {
            let l = dot(d, d).sqrt();
            cable::strain_energy(&self.twine, (l - self.twine.l0) / self.twine.l0)
        };
        self.area_uv * (w(u) + w(v))
    }

    /// The twine family ("U" or "V") whose vector reversed its direction between positions
    /// `x0` and `x1` while it resisted (taut at either end, or r_c > 0): the true motion would
    /// have passed through zero length (the step guard, docs/theory/fem.md#step-control).
    pub(crate) fn turned_over(&self, x0: &[[f64; 3]], x1: &[[f64; 3]]) -> Option<&'static str> {
        let (u0, v0) = self.twine_vectors(x0);
        let (u1, v1) = self.twine_vectors(x1);
        let l0 = self.twine.l0;
        [("U", u0, u1), ("V", v0, v1)]
            .into_iter()
            .find(|&(_, a, b)| {
                let taut = dot(a, a) > l0 * l0 || dot(b, b) > l0 * l0;
                dot(a, b) < 0.0 && (taut || self.twine.rc > 0.0)
            })
            .map(|(f, _, _)| f)
    }

    /// Internal force ∂E/∂x_k on each corner k at node positions `x` (all nodes), static law
    /// (no damping): A_uv·(a_k·T_u·û + b_k·T_v·v̂) [N]; the force the twines apply to the node is
    /// its negative.
    pub fn internal_forces(&self, x: &[[f64; 3]]) -> [[f64; 3]; 3] {
        let mut ev = NetTriangleEval::default();
        evaluate(self, x, x, false, 0.0, false, None, &mut ev);
        std::array::from_fn(|k| ev.force(self, k))
    }

    /// The exact tangent ∂²E/∂x² [N/m] at node positions `x` (all nodes), static law, rows and
    /// columns ordered (corner, component): 9×9.
    pub fn tangent(&self, x: &[[f64; 3]]) -> [[f64; 9]; 9] {
        let mut ev = NetTriangleEval::default();
        evaluate(self, x, x, false, 0.0, false, None, &mut ev);
        let mut k = [[0.0; 9]; 9];
        for i in 0..3 {
            for j in 0..3 {
                let b = ev.block(self, i, j, 1.0, 0.0);
                for r in 0..3 {
                    for c in 0..3 {
                        k[3 * i + r][3 * j + c] = b[r][c];
                    }
                }
            }
        }
        k
    }
}

/// The positions at the start and end of a step (all nodes) [m].
pub(crate) type StepEnds<'a> = (&'a [[f64; 3]], &'a [[f64; 3]]);

/// One net triangle evaluated at a state: each twine family as a cable from 0 to u (v).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct NetTriangleEval {
    /// The U twine: tension, strain, force T·û (`force_b`), 3×3 tangents ∂/∂u, ∂/∂u̇.
    pub u: CableEval,
    /// The V twine.
    pub v: CableEval,
    /// Strain energy A_uv·(W(|u|) + W(|v|)) at the evaluation state [J].
    pub energy: f64,
}

impl NetTriangleEval {
    /// Degenerate (a twine vector of zero length) or non-finite.
    pub fn bad(&self) -> bool {
        self.u.bad || self.v.bad
    }

    /// q-sense internal force on corner k: ∂E/∂x_k = A_uv·(a_k·T_u·û + b_k·T_v·v̂) [N].
    #[inline]
    pub fn force(&self, t: &NetTriangle, k: usize) -> [f64; 3] {
        let (wa, wb) = (t.area_uv * t.grad_u[k], t.area_uv * t.grad_v[k]);
        std::array::from_fn(|i| wa * self.u.force_b[i] + wb * self.v.force_b[i])
    }

    /// Block (i, j) of k·K + c·C: A_uv·(a_i·a_j·(k·K_u + c·C_u) + b_i·b_j·(k·K_v + c·C_v)), with
    /// K_u = ∂(T_u·û)/∂u and C_u = ∂(T_u·û)/∂u̇ the cable's 3×3 tangents.
    #[inline]
    pub fn block(&self, t: &NetTriangle, i: usize, j: usize, k: f64, c: f64) -> [[f64; 3]; 3] {
        let wu = t.area_uv * t.grad_u[i] * t.grad_u[j];
        let wv = t.area_uv * t.grad_v[i] * t.grad_v[j];
        let (u, v) = (&self.u, &self.v);
        std::array::from_fn(|r| {
            std::array::from_fn(|s| {
                wu * (k * u.k[r][s] + c * u.c[r][s]) + wv * (k * v.k[r][s] + c * v.c[r][s])
            })
        })
    }

    /// Damping power of the triangle's twines, A_uv·Σ T_d·ε̇·l_p ≥ 0 [W].
    pub fn damping_power(&self, t: &NetTriangle) -> f64 {
        t.area_uv
            * t.twine.l0
            * (self.u.damping_force * self.u.strain_rate
                + self.v.damping_force * self.v.strain_rate)
    }
}

/// Evaluates triangle `t` at positions `x` and velocities `v` (all nodes). `damping` enables
/// the twines' axial damping, `extra_ca` adds a damping coefficient [N·s] per twine (Rayleigh
/// a_K·EA), `clamp_geometric` uses max(T, 0) in the geometric stiffness of slack twines;
/// `secant` = Some((x_n, x_{n+1})) replaces the elastic force by the discrete gradient between
/// the step's ends (x is then their midpoint; docs/theory/fem.md#energy-consistent-midpoint).
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn evaluate(
    t: &NetTriangle,
    x: &[[f64; 3]],
    v: &[[f64; 3]],
    damping: bool,
    extra_ca: f64,
    clamp_geometric: bool,
    secant: Option<StepEnds<'_>>,
    out: &mut NetTriangleEval,
) {
    let (u, w) = t.twine_vectors(x);
    let (ud, wd) = t.twine_vectors(v);
    let o = [0.0; 3];
    let e = &t.twine;
    out.u = cable::evaluate(e, o, u, o, ud, damping, extra_ca, clamp_geometric);
    out.v = cable::evaluate(e, o, w, o, wd, damping, extra_ca, clamp_geometric);
    out.energy =
        t.area_uv * (cable::strain_energy(e, out.u.strain) + cable::strain_energy(e, out.v.strain));
    if let Some((x0, x1)) = secant {
        let (u0, w0) = t.twine_vectors(x0);
        let (u1, w1) = t.twine_vectors(x1);
        cable::use_secant_tension(e, dot(u0, u0).sqrt(), u1, &mut out.u);
        cable::use_secant_tension(e, dot(w0, w0).sqrt(), w1, &mut out.v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_gradients_reproduce_an_affine_map_in_either_orientation() {
        let s = NetTriangleSection::new(1e3, 0.1, 1e-3);
        let uv = [[0.3, -0.2], [2.1, 0.4], [0.7, 1.9]];
        let map = |p: [f64; 2]| {
            [
                1.5 * p[0] - 0.2 * p[1] + 3.0,
                0.4 * p[0] + 0.9 * p[1],
                0.1 * p[1],
            ]
        };
        for uv in [uv, [uv[0], uv[2], uv[1]]] {
            let t = NetTriangle::new([0, 1, 2], uv, 0, &s).unwrap();
            let x: Vec<[f64; 3]> = uv.iter().map(|&p| map(p)).collect();
            let (u, v) = t.twine_vectors(&x);
            for (got, want) in [(u, [1.5, 0.4, 0.0]), (v, [-0.2, 0.9, 0.1])] {
                for k in 0..3 {
                    assert!((got[k] - want[k]).abs() < 1e-12, "{got:?} vs {want:?}");
                }
            }
            let a = NetTriangle::signed_uv_area(uv).abs();
            assert!((t.uv_area() - a).abs() < 1e-14);
        }
        assert!(NetTriangle::new([0, 1, 2], [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], 0, &s).is_none());
    }

    /// The step guard: a taut U family whose vector reverses is reported; a slack one that
    /// folds through (tension-only, nothing resists) is not, unless r_c > 0.
    #[test]
    fn a_twine_family_that_reverses_while_taut_is_caught() {
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let s = NetTriangleSection::new(1e3, 0.1, 1e-3);
        let t = NetTriangle::new([0, 1, 2], uv, 0, &s).unwrap();
        let x0 = [[0.0; 3], [0.11, 0.0, 0.0], [0.0, 0.1, 0.0]];
        let x1 = [[0.0; 3], [-0.05, 0.0, 0.0], [0.0, 0.1, 0.0]];
        assert_eq!(t.turned_over(&x0, &x1), Some("U"));
        assert_eq!(t.turned_over(&x0, &x0), None);
        let slack = [[0.0; 3], [0.05, 0.0, 0.0], [0.0, 0.1, 0.0]];
        assert_eq!(t.turned_over(&slack, &x1), None);
        let t = NetTriangle::new([0, 1, 2], uv, 0, &s.with_compression_ratio(0.1)).unwrap();
        assert_eq!(t.turned_over(&slack, &x1), Some("U"));
    }
}
