//! Discrete elastic rod (a pipe): bending about both axes of a material frame and torsion, with
//! the exact gradient and tangent (docs/theory/fem.md#rod).
//!
//! A rod is a chain of nodes x_j with edges e_j = x_{j+1} − x_j. Each edge carries a twist angle
//! θ_j [rad], a degree of freedom held as the first coordinate of an auxiliary *twist carrier*
//! node (its other two coordinates held), so the solvers integrate it like any coordinate. The
//! edge's reference director d_j is its director at the last accepted state, parallel
//! transported to the current tangent t_j = e_j/|e_j| (the time-parallel reference frame of
//! Bergou et al. 2010); the material frame is (m1, m2) = (d, t×d) turned by θ_j about t_j.
//!
//! At a vertex i between edges a = i−1 and b = i, with l̄ = |ē_a| + |ē_b| (as built):
//!
//! ```text
//! κb = 2·t_a×t_b/(1 + t_a·t_b)                       curvature binormal
//! ω^j = (κb·m2_j, −κb·m1_j),  j ∈ {a, b}             material curvatures
//! m   = ∠(P_{a→b} m1_a, m1_b) about t_b              twist across the vertex
//! W   = EI/(2 l̄)·Σ_j |ω^j − ω̄^j|² + GJ/l̄·(m − m̄)²
//! ```
//!
//! with ω̄, m̄ of the as-built shape at θ = 0 (P_{a→b} the parallel transport from t_a to t_b), so
//! the as-built shape is force free and a curved member keeps the side its curvature is on.
//! W is a function of the two edge vectors and the two twists (8 variables); its gradient and
//! Hessian come from forward-mode automatic differentiation (`dual.rs`), exact to round-off.

use crate::dual::{Dual1, Dual2, Real};
use serde::{Deserialize, Serialize};

/// Number of local DOFs of a rod vertex: three nodes (9) and two twists.
pub(crate) const ROD_DOFS: usize = 11;

/// Reference frame of a rod edge: unit tangent and a unit director normal to it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EdgeFrame {
    /// Unit tangent t of the edge when the frame was set.
    pub tangent: [f64; 3],
    /// Unit reference director d ⊥ t.
    pub director: [f64; 3],
}

impl EdgeFrame {
    /// This frame carried to the edge direction `e` by parallel transport.
    pub(crate) fn transported(&self, e: [f64; 3]) -> Option<Self> {
        let n = norm(e);
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let t = e.map(|c| c / n);
        if dot(self.tangent, t) < -0.99 {
            return None;
        }
        let d = transport(self.tangent, self.director, t);
        let dn = norm(d);
        Some(Self {
            tangent: t,
            director: d.map(|c| c / dn),
        })
    }

    /// A frame for the edge `e` with the director chosen from the global axis least aligned with
    /// it; `None` for a zero edge.
    pub(crate) fn for_edge(e: [f64; 3]) -> Option<Self> {
        let n = norm(e);
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let t = e.map(|c| c / n);
        let k = (0..3)
            .min_by(|&i, &j| t[i].abs().total_cmp(&t[j].abs()))
            .unwrap_or(2);
        // Prefer the vertical axis unless the edge is close to vertical (a collar's director
        // then points up).
        let k = if t[2].abs() < 0.9 { 2 } else { k };
        let mut a = [0.0; 3];
        a[k] = 1.0;
        let s = dot(a, t);
        let d = [a[0] - s * t[0], a[1] - s * t[1], a[2] - s * t[2]];
        let dn = norm(d);
        Some(Self {
            tangent: t,
            director: d.map(|c| c / dn),
        })
    }
}

/// A rod vertex: bending and torsion between two consecutive edges (resolved properties).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodVertex {
    /// Nodes x_{i−1}, x_i, x_{i+1}.
    pub nodes: [usize; 3],
    /// Twist carrier nodes of edges a = (x_{i−1}, x_i) and b = (x_i, x_{i+1}).
    pub carriers: [usize; 2],
    /// Rod edge indices of a and b.
    pub edges: [usize; 2],
    /// Bending stiffness EI [N·m²].
    pub ei: f64,
    /// Torsional stiffness GJ [N·m²].
    pub gj: f64,
    /// l̄ = |ē_a| + |ē_b| of the as-built edges [m] (twice the vertex's Voronoi length).
    pub length: f64,
    /// As-built material curvatures ω̄^a, ω̄^b (dimensionless).
    pub rest_curvature: [[f64; 2]; 2],
    /// As-built twist m̄ across the vertex [rad].
    pub rest_twist: f64,
}

/// A rod edge: its nodes, its twist carrier and its cable element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodEdge {
    /// Nodes (x_j, x_{j+1}).
    pub nodes: [usize; 2],
    /// Node whose first coordinate is the edge's twist θ [rad].
    pub carrier: usize,
    /// The cable element joining the two nodes (axial stiffness and mass), if any.
    pub element: Option<usize>,
    /// As-built reference frame.
    pub frame: EdgeFrame,
}

/// Result of evaluating one rod vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RodEval {
    /// Energy W [J].
    pub energy: f64,
    /// ∂W/∂(x_{i−1}, x_i, x_{i+1}, θ_a, θ_b) [N, N·m].
    pub force: [f64; ROD_DOFS],
    /// ∂²W over the same DOFs.
    pub k: [[f64; ROD_DOFS]; ROD_DOFS],
    /// Bending moment |M| at the vertex [N·m].
    pub moment: f64,
    /// Torque at the vertex [N·m].
    pub torque: f64,
    /// Degenerate (zero edge, folded back) or non-finite.
    pub bad: bool,
}

impl Default for RodEval {
    fn default() -> Self {
        Self {
            energy: 0.0,
            force: [0.0; ROD_DOFS],
            k: [[0.0; ROD_DOFS]; ROD_DOFS],
            moment: 0.0,
            torque: 0.0,
            bad: false,
        }
    }
}

/// The 8 variables of a vertex: e_a, e_b, θ_a, θ_b.
pub(crate) type Vars = [f64; 8];

/// Vertex variables from the node positions and the twists.
pub(crate) fn vars(x: [[f64; 3]; 3], theta: [f64; 2]) -> Vars {
    let ea = sub(x[1], x[0]);
    let eb = sub(x[2], x[1]);
    [ea[0], ea[1], ea[2], eb[0], eb[1], eb[2], theta[0], theta[1]]
}

/// Material curvatures (ω^a, ω^b) and twist m at the variables `y`, with reference frames
/// `fa`, `fb`; generic over dual numbers.
fn kinematics<D: Real>(fa: &EdgeFrame, fb: &EdgeFrame, y: &[D; 8]) -> ([[D; 2]; 2], D) {
    let ta = unit([y[0], y[1], y[2]]);
    let tb = unit([y[3], y[4], y[5]]);
    let (m1a, m2a) = material(fa, ta, y[6]);
    let (m1b, m2b) = material(fb, tb, y[7]);
    let c = dot(ta, tb);
    let kb = cross(ta, tb).map(|v| v * 2.0 / (c + 1.0));
    let omega = [[dot(kb, m2a), -dot(kb, m1a)], [dot(kb, m2b), -dot(kb, m1b)]];
    let p = transport(ta, m1a, tb);
    let twist = dot(cross(p, m1b), tb).atan2(dot(p, m1b));
    (omega, twist)
}

/// Material frame (m1, m2) of an edge of unit tangent t and twist θ.
fn material<D: Real>(f: &EdgeFrame, t: [D; 3], theta: D) -> ([D; 3], [D; 3]) {
    let d1 = transport(f.tangent.map(D::cst), f.director.map(D::cst), t);
    let d2 = cross(t, d1);
    let (s, c) = (theta.sin(), theta.cos());
    (
        [
            d1[0] * c + d2[0] * s,
            d1[1] * c + d2[1] * s,
            d1[2] * c + d2[2] * s,
        ],
        [
            d2[0] * c - d1[0] * s,
            d2[1] * c - d1[1] * s,
            d2[2] * c - d1[2] * s,
        ],
    )
}

/// Energy W of vertex `v` at the variables `y`.
fn energy_of<D: Real>(v: &RodVertex, fa: &EdgeFrame, fb: &EdgeFrame, y: &[D; 8]) -> D {
    let (omega, twist) = kinematics(fa, fb, y);
    let mut bend = D::cst(0.0);
    for j in 0..2 {
        for k in 0..2 {
            let d = omega[j][k] + (-v.rest_curvature[j][k]);
            bend = bend + d * d;
        }
    }
    let dm = twist + (-v.rest_twist);
    bend * (0.5 * v.ei / v.length) + dm * dm * (v.gj / v.length)
}

/// Rest material curvatures and twist of the edges e_a, e_b with frames fa, fb (θ = 0).
pub(crate) fn rest_state(
    fa: &EdgeFrame,
    fb: &EdgeFrame,
    ea: [f64; 3],
    eb: [f64; 3],
) -> ([[f64; 2]; 2], f64) {
    let y = [ea[0], ea[1], ea[2], eb[0], eb[1], eb[2], 0.0, 0.0];
    kinematics(fa, fb, &y)
}

/// Energy W [J] of vertex `v` at the variables `y`.
pub(crate) fn energy(v: &RodVertex, fa: &EdgeFrame, fb: &EdgeFrame, y: &Vars) -> f64 {
    energy_of(v, fa, fb, y)
}

/// Weights of the discrete gradient's metric: 1 for edge components, (l̄/2)² for twists.
fn metric(v: &RodVertex) -> [f64; 8] {
    let w = 0.25 * v.length * v.length;
    [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, w, w]
}

/// Evaluates vertex `v` at the variables `y` into `out` (tangent only if `tangent`). With
/// `ends = Some((y0, y1))` the force is the discrete gradient between the step's ends
/// (docs/theory/fem.md#energy-consistent-midpoint) and `y` must be their mean; the tangent is
/// the midpoint Hessian.
pub(crate) fn evaluate(
    v: &RodVertex,
    fa: &EdgeFrame,
    fb: &EdgeFrame,
    y: &Vars,
    ends: Option<(&Vars, &Vars)>,
    tangent: bool,
    out: &mut RodEval,
) {
    let ea = norm([y[0], y[1], y[2]]);
    let eb = norm([y[3], y[4], y[5]]);
    let c = (y[0] * y[3] + y[1] * y[4] + y[2] * y[5]) / (ea * eb);
    if !(ea > 0.0 && eb > 0.0 && c > -0.99) {
        out.bad = true;
        out.energy = f64::INFINITY;
        return;
    }
    let (w, mut g) = if tangent {
        let z: [Dual2<8>; 8] = std::array::from_fn(|i| Dual2::var(y[i], i));
        let e = energy_of(v, fa, fb, &z);
        to_nodes_k(&e.h, &mut out.k);
        (e.v, e.g)
    } else {
        let z: [Dual1<8>; 8] = std::array::from_fn(|i| Dual1::var(y[i], i));
        let e = energy_of(v, fa, fb, &z);
        (e.v, e.g)
    };
    out.energy = w;
    if let Some((y0, y1)) = ends {
        // Gonzalez's discrete gradient: g + (W1 − W0 − g·Δ)/(ΔᵀWΔ)·WΔ.
        let wgt = metric(v);
        let (w0, w1) = (energy(v, fa, fb, y0), energy(v, fa, fb, y1));
        let (mut gd, mut dd) = (0.0, 0.0);
        let mut delta = [0.0; 8];
        for i in 0..8 {
            delta[i] = y1[i] - y0[i];
            gd += g[i] * delta[i];
            dd += wgt[i] * delta[i] * delta[i];
        }
        if dd > 1e-300 {
            let corr = (w1 - w0 - gd) / dd;
            for i in 0..8 {
                g[i] += corr * wgt[i] * delta[i];
            }
        }
    }
    out.force = to_nodes_f(&g);
    let (omega, twist) = kinematics(fa, fb, y);
    let half = 0.5 * v.length;
    let m1 = 0.5 * (omega[0][0] - v.rest_curvature[0][0] + omega[1][0] - v.rest_curvature[1][0]);
    let m2 = 0.5 * (omega[0][1] - v.rest_curvature[0][1] + omega[1][1] - v.rest_curvature[1][1]);
    out.moment = v.ei * (m1 * m1 + m2 * m2).sqrt() / half;
    out.torque = v.gj * (twist - v.rest_twist) / half;
    out.bad = !(w.is_finite() && g.iter().all(|c| c.is_finite()));
    if tangent {
        out.bad |= !out.k.iter().flatten().all(|c| c.is_finite());
    }
}

/// Edge-variable gradient to the vertex DOFs (x_{i−1}, x_i, x_{i+1}, θ_a, θ_b):
/// e_a = x_i − x_{i−1}, e_b = x_{i+1} − x_i.
fn to_nodes_f(g: &[f64; 8]) -> [f64; ROD_DOFS] {
    let mut f = [0.0; ROD_DOFS];
    for k in 0..3 {
        f[k] = -g[k];
        f[3 + k] = g[k] - g[3 + k];
        f[6 + k] = g[3 + k];
    }
    f[9] = g[6];
    f[10] = g[7];
    f
}

/// The map B (8 × 11) from vertex DOFs to edge variables, as (variable, dof, coefficient).
fn b_entries(var: usize) -> [(usize, f64); 2] {
    match var {
        0..=2 => [(var, -1.0), (3 + var, 1.0)],
        3..=5 => [(var, -1.0), (3 + var, 1.0)],
        6 => [(9, 1.0), (9, 0.0)],
        _ => [(10, 1.0), (10, 0.0)],
    }
}

/// Edge-variable Hessian to the vertex DOFs: K = Bᵀ·H·B.
fn to_nodes_k(h: &[[f64; 8]; 8], k: &mut [[f64; ROD_DOFS]; ROD_DOFS]) {
    for row in k.iter_mut() {
        *row = [0.0; ROD_DOFS];
    }
    for p in 0..8 {
        for q in 0..8 {
            let hpq = h[p][q];
            if hpq == 0.0 {
                continue;
            }
            for (dp, cp) in b_entries(p) {
                for (dq, cq) in b_entries(q) {
                    k[dp][dq] += cp * cq * hpq;
                }
            }
        }
    }
}

fn transport<D: Real>(a: [D; 3], v: [D; 3], b: [D; 3]) -> [D; 3] {
    // Rotation about a×b taking unit a to unit b: R·v = c·v + w×v + (w·v)/(1 + c)·w.
    let c = dot(a, b);
    let w = cross(a, b);
    let wx = cross(w, v);
    let s = dot(w, v) / (c + 1.0);
    [
        v[0] * c + wx[0] + w[0] * s,
        v[1] * c + wx[1] + w[1] * s,
        v[2] * c + wx[2] + w[2] * s,
    ]
}

fn unit<D: Real>(e: [D; 3]) -> [D; 3] {
    let n = dot(e, e).sqrt();
    e.map(|c| c / n)
}

fn dot<D: Real>(a: [D; 3], b: [D; 3]) -> D {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<D: Real>(a: [D; 3], b: [D; 3]) -> [D; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(x: [[f64; 3]; 3]) -> (RodVertex, EdgeFrame, EdgeFrame) {
        let ea = sub(x[1], x[0]);
        let eb = sub(x[2], x[1]);
        let fa = EdgeFrame::for_edge(ea).unwrap();
        let fb = fa.transported(eb).unwrap();
        let (rest_curvature, rest_twist) = rest_state(&fa, &fb, ea, eb);
        let v = RodVertex {
            nodes: [0, 1, 2],
            carriers: [3, 4],
            edges: [0, 1],
            ei: 3.0,
            gj: 2.0,
            length: norm(ea) + norm(eb),
            rest_curvature,
            rest_twist,
        };
        (v, fa, fb)
    }

    #[test]
    fn force_and_tangent_are_the_derivatives_of_the_energy() {
        let x = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.1], [1.8, 0.9, 0.0]];
        let (v, fa, fb) = vertex(x);
        let y = vars(
            [[0.1, -0.05, 0.02], [0.9, 0.3, 0.2], [1.9, 0.7, -0.1]],
            [0.2, -0.3],
        );
        let mut ev = RodEval::default();
        evaluate(&v, &fa, &fb, &y, None, true, &mut ev);
        assert!(!ev.bad);
        let h = 1e-6;
        // Perturb the 11 DOFs through the node positions and twists.
        let pos = |d: usize, s: f64| {
            let mut xs = [
                [0.0, 0.0, 0.0],
                [y[0], y[1], y[2]],
                [y[0] + y[3], y[1] + y[4], y[2] + y[5]],
            ];
            let mut th = [y[6], y[7]];
            if d < 9 {
                xs[d / 3][d % 3] += s;
            } else {
                th[d - 9] += s;
            }
            vars(xs, th)
        };
        for d in 0..ROD_DOFS {
            let (yp, ym) = (pos(d, h), pos(d, -h));
            let fd = (energy(&v, &fa, &fb, &yp) - energy(&v, &fa, &fb, &ym)) / (2.0 * h);
            assert!(
                (fd - ev.force[d]).abs() < 1e-6 * (1.0 + fd.abs()),
                "force {d}: {fd} vs {}",
                ev.force[d]
            );
            let (mut ep, mut em) = (RodEval::default(), RodEval::default());
            evaluate(&v, &fa, &fb, &yp, None, false, &mut ep);
            evaluate(&v, &fa, &fb, &ym, None, false, &mut em);
            for r in 0..ROD_DOFS {
                let kfd = (ep.force[r] - em.force[r]) / (2.0 * h);
                assert!(
                    (kfd - ev.k[r][d]).abs() < 1e-5 * (1.0 + kfd.abs()),
                    "k[{r}][{d}]: {kfd} vs {}",
                    ev.k[r][d]
                );
            }
        }
    }

    #[test]
    fn as_built_and_rigid_motions_are_force_free() {
        let x = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [1.8, 0.9, 0.1]];
        let (v, fa, fb) = vertex(x);
        let mut ev = RodEval::default();
        evaluate(&v, &fa, &fb, &vars(x, [0.0; 2]), None, true, &mut ev);
        assert!(
            ev.energy < 1e-28 && ev.force.iter().all(|f| f.abs() < 1e-12),
            "{ev:?}"
        );
        // A uniform twist of both edges on a straight rod costs nothing; on a curved vertex it
        // turns the curvature away from its side and costs bending energy.
        let straight = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let (vs, fsa, fsb) = vertex(straight);
        assert!(energy(&vs, &fsa, &fsb, &vars(straight, [0.7, 0.7])) < 1e-28);
        assert!(energy(&v, &fa, &fb, &vars(x, [0.7, 0.7])) > 1e-3);
        // Twist across the vertex: W = GJ·Δθ²/l̄ on a straight rod.
        let w = energy(&vs, &fsa, &fsb, &vars(straight, [0.0, 0.1]));
        assert!((w - 2.0 * 0.01 / 2.0).abs() < 1e-14, "{w}");
    }

    #[test]
    fn bending_the_curvature_inside_out_costs_four_times_as_much() {
        // A planar curved vertex bent to the opposite curvature (−κ̄) against the same vertex
        // straightened (0): the hinge of |κb| cannot tell −κ̄ from κ̄; the rod can.
        let phi = 0.2f64;
        let x = [[0.0; 3], [1.0, 0.0, 0.0], [1.0 + phi.cos(), phi.sin(), 0.0]];
        let (v, fa, fb) = vertex(x);
        let flip = [
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0 + phi.cos(), -phi.sin(), 0.0],
        ];
        let straight = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let wf = energy(&v, &fa, &fb, &vars(flip, [0.0; 2]));
        let ws = energy(&v, &fa, &fb, &vars(straight, [0.0; 2]));
        assert!((wf / ws - 4.0).abs() < 1e-12, "{wf} {ws}");
    }

    #[test]
    fn discrete_gradient_gives_the_exact_energy_change() {
        let x = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [1.8, 0.9, 0.1]];
        let (v, fa, fb) = vertex(x);
        let y0 = vars(x, [0.0, 0.0]);
        let y1 = vars(
            [[0.1, 0.0, 0.3], [1.0, 0.5, 0.2], [1.5, 1.1, -0.2]],
            [0.3, -0.2],
        );
        let ym: Vars = std::array::from_fn(|i| 0.5 * (y0[i] + y1[i]));
        let mut ev = RodEval::default();
        evaluate(&v, &fa, &fb, &ym, Some((&y0, &y1)), false, &mut ev);
        // Work of the discrete gradient over the step, through the edge variables.
        let g = [
            -ev.force[0],
            -ev.force[1],
            -ev.force[2],
            ev.force[6],
            ev.force[7],
            ev.force[8],
            ev.force[9],
            ev.force[10],
        ];
        let work: f64 = (0..8).map(|i| g[i] * (y1[i] - y0[i])).sum();
        let dw = energy(&v, &fa, &fb, &y1) - energy(&v, &fa, &fb, &y0);
        assert!(
            (work - dw).abs() < 1e-12 * dw.abs().max(1.0),
            "{work} vs {dw}"
        );
    }
}
