//! Nonlinear relaxation of free lines inside a dynamic Newton iteration
//! (docs/theory/fem.md#line-relaxation).
//!
//! A *line* is a maximal chain of interior nodes that each join exactly two cable elements,
//! have all three DOFs free, carry no bending hinge and no net triangle, and share load
//! elements only with their line neighbours; its two *ends* are the nodes beyond (an anchor,
//! a plate, a collar node).
//! After each global Newton update x^{k+1} = x^k + Δx, the interior of every line is moved so
//! that, with its ends held at x^{k+1}, the model
//!
//! ```text
//! r_loc(x) = J_ii·(x − x^{k+1}) + w·(F(x) − F(x^k)) − J_F(x^k)·(x − x^k)
//! ```
//!
//! vanishes on the interior rows: the global linear model that the Newton update satisfied,
//! plus the nonlinear remainder of the line's own cable forces and, with HHT-α, of the seabed's
//! normal force on its interior nodes, F (w = 1 for the midpoint rule, 1 − α for HHT-α; J_F
//! their part of the Jacobian). Everything else (inertia, water loads, seabed friction, and the
//! seabed with the midpoint rule) keeps its linearisation. A tension-only element that the update stretches from
//! slack to taut makes this remainder large, and the local Newton iterations that remove it —
//! one block-tridiagonal solve each, microseconds for a line of 40 elements — carry the
//! tightening along the line, which the global Newton would do one element per factorisation.
//! The seabed's kink at touchdown is settled the same way: a node that the update moves
//! across the bed plane (or through the damping ramp) would otherwise make the global
//! iteration converge linearly there (docs/theory/fem.md#line-relaxation-seabed).
//! Near the solution the remainder is O(|Δx|²), so Newton's quadratic convergence is kept.
//! A line whose local solve ends with a larger remainder than it began with is left at
//! x^{k+1}.

use crate::cable;
use crate::dynamics::{ForceEvaluation, Scheme};
use crate::model::{Cable, Model};
use crate::seabed::BedLaw;
use crate::system::{Coef, NONE, System, norm, sub};
use nalgebra::{Matrix3, Vector3};

/// Local Newton iterations per line and global iteration.
const MAX_LOCAL_ITERATIONS: usize = 60;

/// The local solve stops when the remainder is below this fraction of where it began (or
/// below the caller's floor).
const LOCAL_REDUCTION: f64 = 1e-6;

/// Strain above which an element that was slack counts as tightened [-].
const TIGHTENED_STRAIN: f64 = 1e-6;

/// One line: interior nodes in order, its ends, its elements in order and the positions of
/// its Jacobian blocks in the global matrix.
#[derive(Debug)]
struct Line {
    nodes: Vec<usize>,
    ends: [usize; 2],
    /// Element j joins node j − 1 and node j of [end0, nodes…, end1].
    elems: Vec<usize>,
    /// Position in `values` of block (i, j), row-major 3×3, for j = i − 1, i, i + 1.
    blocks: Vec<[[usize; 9]; 3]>,
    /// Interior positions of the nodes that can touch the seabed.
    bed: Vec<usize>,
}

/// The kinematics of the step that turn x_{n+1} into the state the equations are evaluated
/// at.
pub(crate) struct StepKinematics<'a> {
    /// The time scheme: its kinematics and how it evaluates the step's forces.
    pub scheme: &'a Scheme,
    pub h: f64,
    pub xn: &'a [[f64; 3]],
    pub vn: &'a [[f64; 3]],
    pub an: &'a [[f64; 3]],
    /// Evaluation state of the last evaluation (for constrained DOFs).
    pub x_eval: &'a [[f64; 3]],
    pub v_eval: &'a [[f64; 3]],
    pub coef: Coef,
    /// Weight of the internal forces in the residual.
    pub weight: f64,
    /// Stiffness-proportional Rayleigh coefficient a_K [s].
    pub a_k: f64,
    pub clamp: bool,
}

/// The lines of a model and the scratch of their local solves.
#[derive(Debug, Default)]
pub(crate) struct LineRelaxation {
    lines: Vec<Line>,
    scratch: Scratch,
    /// Local Newton iterations over the run.
    pub local_iterations: usize,
    /// Line solves that were kept / left at the global update.
    pub kept: usize,
    pub reverted: usize,
    /// Most local iterations of one line in the last `relax` among the lines in which an
    /// element that was slack at x^k ended taut (strain ≥ [`TIGHTENED_STRAIN`]): a
    /// tightening front moves about one element per local iteration.
    pub last_front: usize,
}

/// Buffers of one line's local solve, kept between calls (no allocation per iteration).
#[derive(Debug, Default)]
struct Scratch {
    at_k: Vec<ElementLinear>,
    now: Vec<ElementLinear>,
    start: Vec<[f64; 3]>,
    r: Vec<[f64; 3]>,
    delta: Vec<[f64; 3]>,
    diag: Vec<Matrix3<f64>>,
    lower: Vec<Matrix3<f64>>,
    upper: Vec<Matrix3<f64>>,
    inv: Vec<Matrix3<f64>>,
    rhs: Vec<Vector3<f64>>,
    /// Per bed node of the line: the seabed's q-sense force −f_z and its Jacobian entry at x^k,
    /// and that entry at the current x.
    bed_k: Vec<(f64, f64)>,
    bed_now: Vec<f64>,
}

/// One element's force on its node b (q sense, unweighted) and its Jacobian block.
#[derive(Debug, Clone, Copy, Default)]
struct ElementLinear {
    force_b: [f64; 3],
    blk: [[f64; 3]; 3],
}

impl LineRelaxation {
    /// Finds the lines of `model` (none when the mass matrix couples more than lines do, or
    /// the pattern lacks an entry).
    pub(crate) fn new(model: &Model, sys: &System) -> Self {
        let n = model.n_nodes();
        let elements = model.elements();
        let mut node_elems = vec![Vec::new(); n];
        for (ie, e) in elements.iter().enumerate() {
            node_elems[e.a].push(ie);
            node_elems[e.b].push(ie);
        }
        let other = |ie: usize, i: usize| {
            let e = &elements[ie];
            if e.a == i { e.b } else { e.a }
        };
        let mut eligible = vec![false; n];
        for i in 0..n {
            let ok = node_elems[i].len() == 2
                && other(node_elems[i][0], i) != other(node_elems[i][1], i)
                && (0..3).all(|k| sys.free_of_dof[3 * i + k] != NONE);
            eligible[i] = ok;
        }
        for h in model.hinges() {
            for &nd in &h.nodes {
                eligible[nd] = false;
            }
        }
        // A net triangle couples its corners to nodes off the chain and is not in the local
        // model: its nodes are no line's interior (docs/theory/fem.md#net-triangle).
        for t in model.net_triangles() {
            for &nd in &t.nodes {
                eligible[nd] = false;
            }
        }
        // A rigid link joins its point to the body's centre and carrier, off the chain.
        for l in &model.links {
            eligible[l.node] = false;
        }
        for nodes in sys.load_element_nodes() {
            for &i in nodes {
                if !eligible[i] {
                    continue;
                }
                let neighbours = [other(node_elems[i][0], i), other(node_elems[i][1], i)];
                let fits = nodes.len() == 1
                    || (nodes.len() == 2
                        && nodes.iter().all(|&j| j == i || neighbours.contains(&j)));
                if !fits {
                    eligible[i] = false;
                }
            }
        }
        let mut seen = vec![false; n];
        let mut lines = Vec::new();
        let law = BedLaw::new(model, true);
        for start in 0..n {
            if !eligible[start] || seen[start] {
                continue;
            }
            // Walk to one end, then collect the chain from there.
            let (mut prev_e, mut cur) = (node_elems[start][0], start);
            let mut guard = 0;
            loop {
                let next_e = if node_elems[cur][0] == prev_e {
                    node_elems[cur][1]
                } else {
                    node_elems[cur][0]
                };
                let nxt = other(next_e, cur);
                guard += 1;
                if !eligible[nxt] || nxt == start || guard > n {
                    prev_e = next_e;
                    break;
                }
                prev_e = next_e;
                cur = nxt;
            }
            // `cur` is an interior node at one end of the chain, `prev_e` its element to the
            // end node.
            let end0 = other(prev_e, cur);
            if eligible[end0] {
                // A closed ring of eligible nodes: no ends to hold.
                let mut c = start;
                let mut pe = node_elems[start][0];
                loop {
                    seen[c] = true;
                    pe = if node_elems[c][0] == pe {
                        node_elems[c][1]
                    } else {
                        node_elems[c][0]
                    };
                    c = other(pe, c);
                    if c == start {
                        break;
                    }
                }
                continue;
            }
            let mut nodes = vec![cur];
            let mut elems = vec![prev_e];
            let (mut pe, mut c) = (prev_e, cur);
            let end1 = loop {
                seen[c] = true;
                let ne = if node_elems[c][0] == pe {
                    node_elems[c][1]
                } else {
                    node_elems[c][0]
                };
                elems.push(ne);
                let nx = other(ne, c);
                if !eligible[nx] {
                    break nx;
                }
                nodes.push(nx);
                pe = ne;
                c = nx;
            };
            if nodes.len() < 2 {
                continue;
            }
            let mut blocks = Vec::with_capacity(nodes.len());
            let mut complete = true;
            for (p, &i) in nodes.iter().enumerate() {
                let mut b = [[NONE; 9]; 3];
                for (s, q) in [p.checked_sub(1), Some(p), Some(p + 1)]
                    .into_iter()
                    .enumerate()
                {
                    let Some(j) = q.and_then(|q| nodes.get(q)) else {
                        continue;
                    };
                    for ki in 0..3 {
                        for kj in 0..3 {
                            let r = sys.free_of_dof[3 * i + ki];
                            let c = sys.free_of_dof[3 * j + kj];
                            match sys.entry_pos(r, c) {
                                Some(pos) => b[s][3 * ki + kj] = pos,
                                None => complete = false,
                            }
                        }
                    }
                }
                blocks.push(b);
            }
            if complete {
                let bed = (0..nodes.len())
                    .filter(|&p| law.acts_on(model, nodes[p]))
                    .collect();
                lines.push(Line {
                    nodes,
                    ends: [end0, end1],
                    elems,
                    blocks,
                    bed,
                });
            }
        }
        Self {
            lines,
            ..Default::default()
        }
    }

    /// Number of lines found.
    pub(crate) fn n_lines(&self) -> usize {
        self.lines.len()
    }

    /// Relaxes every line from the global update `x` (= x^{k+1}, changed in place) given the
    /// previous iterate `xk`, down to a remainder of `floor` [N] on each line; returns the
    /// largest move of a node [m].
    pub(crate) fn relax(
        &mut self,
        model: &Model,
        sys: &System,
        kin: &StepKinematics<'_>,
        xk: &[[f64; 3]],
        x: &mut [[f64; 3]],
        floor: f64,
    ) -> f64 {
        let mut largest = 0.0f64;
        self.last_front = 0;
        let elements = model.elements();
        let sc = &mut self.scratch;
        let bed = BedLaw::new(model, true);
        // The midpoint rule keeps the seabed linearised: with its discrete-gradient contact the
        // local solves made Newton fail on a chain landing on the bed
        // (docs/theory/fem.md#line-relaxation-seabed).
        let bed_nodes: &[usize] = &[];
        let gradient = kin.scheme.force_evaluation() == ForceEvaluation::DiscreteGradient;
        for line in &self.lines {
            let bed_nodes = if gradient { bed_nodes } else { &line.bed };
            let ctx = Ctx {
                line,
                elements,
                kin,
                sys,
                model,
                bed,
                bed_nodes,
            };
            // The elements at x^k are those of the evaluation that formed J.
            sc.at_k.clear();
            sc.at_k
                .extend(line.elems.iter().map(|&ie| ctx.evaluated(&sys.cable[ie])));
            sc.bed_k.clear();
            sc.bed_k.extend(
                bed_nodes
                    .iter()
                    .map(|&p| ctx.bed_linear(line.nodes[p], xk[line.nodes[p]])),
            );
            sc.start.clear();
            sc.start.extend(line.nodes.iter().map(|&i| x[i]));
            if !ctx.remainder(sc, xk, x) {
                continue;
            }
            let r0 = block_norm(&sc.r);
            if !(r0 > floor) {
                continue;
            }
            let mut rn = r0;
            let mut iterations = 0;
            while rn > (LOCAL_REDUCTION * r0).max(floor) && iterations < MAX_LOCAL_ITERATIONS {
                iterations += 1;
                if !ctx.newton_correction(sc) {
                    break;
                }
                for (p, d) in sc.delta.iter().enumerate() {
                    let i = line.nodes[p];
                    for k in 0..3 {
                        x[i][k] -= d[k];
                    }
                }
                if !ctx.remainder(sc, xk, x) {
                    rn = f64::INFINITY;
                    break;
                }
                rn = block_norm(&sc.r);
            }
            self.local_iterations += iterations;
            if rn.is_finite() && rn < r0 {
                self.kept += 1;
                let tightened = line.elems.iter().any(|&ie| {
                    let e = &elements[ie];
                    sys.cable[ie].strain <= 0.0
                        && norm(sub(x[e.b], x[e.a])) >= (1.0 + TIGHTENED_STRAIN) * e.l0
                });
                if tightened {
                    self.last_front = self.last_front.max(iterations);
                }
                for (p, &i) in line.nodes.iter().enumerate() {
                    for k in 0..3 {
                        largest = largest.max((x[i][k] - sc.start[p][k]).abs());
                    }
                }
            } else {
                self.reverted += 1;
                for (p, &i) in line.nodes.iter().enumerate() {
                    x[i] = sc.start[p];
                }
            }
        }
        largest
    }
}

/// What one line's local solve reads.
struct Ctx<'a, 'b> {
    line: &'a Line,
    elements: &'a [Cable],
    kin: &'a StepKinematics<'b>,
    sys: &'a System,
    model: &'a Model,
    bed: BedLaw,
    /// Interior positions whose seabed force is relaxed with the cables.
    bed_nodes: &'a [usize],
}

impl Ctx<'_, '_> {
    /// The evaluation state (position, velocity) of node i at end position `xi`: the
    /// midpoint's or x_{n+1}'s (constrained DOFs keep the last evaluation's).
    fn eval_state(&self, i: usize, xi: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let kin = self.kin;
        let mut xe = kin.x_eval[i];
        let mut ve = kin.v_eval[i];
        for k in 0..3 {
            if self.sys.free_of_dof[3 * i + k] == NONE {
                continue;
            }
            let (xn, vn, an) = (kin.xn[i][k], kin.vn[i][k], kin.an[i][k]);
            (xe[k], ve[k]) = kin.scheme.evaluation_point(xn, vn, an, xi[k], kin.h);
        }
        (xe, ve)
    }

    /// Force on node b and Jacobian block of element `e` at end positions `x`, as
    /// `System::evaluate` and `assemble_jacobian` form them (NaN force if degenerate).
    fn linear(&self, ie: usize, e: &Cable, x: &[[f64; 3]]) -> ElementLinear {
        let kin = self.kin;
        let (xa, xb) = (x[e.a], x[e.b]);
        let (xea, vea) = self.eval_state(e.a, xa);
        let (xeb, veb) = self.eval_state(e.b, xb);
        let mut ev = cable::evaluate(e, xea, xeb, vea, veb, true, kin.a_k * e.ea, kin.clamp);
        if kin.scheme.force_evaluation() == ForceEvaluation::DiscreteGradient {
            let l0 = norm(sub(kin.xn[e.b], kin.xn[e.a]));
            cable::use_secant_tension(e, l0, sub(xb, xa), &mut ev);
        }
        if let Some(f) = kin.scheme.hht_forces() {
            let d0 = sub(kin.xn[e.b], kin.xn[e.a]);
            crate::dynamics::use_hht_force(e, d0, &f.cable[ie], &f.w, &mut ev);
        }
        let mut blk = [[0.0; 3]; 3];
        for (i, row) in blk.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = kin.coef.k * ev.k[i][j] + kin.coef.c * ev.c[i][j];
            }
        }
        let force_b = if ev.bad { [f64::NAN; 3] } else { ev.force_b };
        ElementLinear { force_b, blk }
    }

    /// The seabed at node i with end position `xi`: its q-sense force −f_z and its entry in J,
    /// as `System::evaluate` and `assemble_jacobian` form them.
    fn bed_linear(&self, i: usize, xi: [f64; 3]) -> (f64, f64) {
        let (xe, ve) = self.eval_state(i, xi);
        let gradient = self.kin.scheme.force_evaluation() == ForceEvaluation::DiscreteGradient;
        let secant = gradient.then(|| (self.kin.xn[i][2], xi[2]));
        let (f, kz, cz) = self.bed.node(self.model, i, xe[2], ve[2], secant);
        (-f, self.kin.coef.k * kz + self.kin.coef.c * cz)
    }

    /// The linearisation of an element as the last evaluation left it.
    fn evaluated(&self, ev: &cable::CableEval) -> ElementLinear {
        let c = self.kin.coef;
        let blk =
            std::array::from_fn(|i| std::array::from_fn(|j| c.k * ev.k[i][j] + c.c * ev.c[i][j]));
        ElementLinear {
            force_b: ev.force_b,
            blk,
        }
    }

    /// Interior index of chain position c, if c is not an end.
    fn interior(&self, c: usize) -> Option<usize> {
        (c >= 1 && c <= self.line.nodes.len()).then(|| c - 1)
    }

    /// Node at chain position c: end 0, the interior nodes, end 1.
    fn chain(&self, c: usize) -> usize {
        let m = self.line.nodes.len();
        if c == 0 {
            self.line.ends[0]
        } else if c == m + 1 {
            self.line.ends[1]
        } else {
            self.line.nodes[c - 1]
        }
    }

    /// r_loc on the interior rows at `x` into `r` and the elements' linearisations there into
    /// `now`; false when an element is degenerate or a force non-finite.
    fn remainder(&self, sc: &mut Scratch, xk: &[[f64; 3]], x: &[[f64; 3]]) -> bool {
        let (at_k, start, r, now) = (&sc.at_k, &sc.start, &mut sc.r, &mut sc.now);
        let line = self.line;
        let m = line.nodes.len();
        let vals = &self.sys.values;
        r.clear();
        r.resize(m, [0.0; 3]);
        // The global linear model: J_ii·(x − x^{k+1}).
        for (p, row) in r.iter_mut().enumerate() {
            for (s, q) in [p.checked_sub(1), Some(p), Some(p + 1)]
                .into_iter()
                .enumerate()
            {
                let Some(q) = q.filter(|&q| q < m) else {
                    continue;
                };
                let j = line.nodes[q];
                let y = sub(x[j], start[q]);
                let b = &line.blocks[p][s];
                for (ki, rk) in row.iter_mut().enumerate() {
                    for (kj, yk) in y.iter().enumerate() {
                        *rk += vals[b[3 * ki + kj]] * yk;
                    }
                }
            }
        }
        // The nonlinear remainder of the line's cable forces.
        let w = self.kin.weight;
        now.clear();
        for (j, &ie) in line.elems.iter().enumerate() {
            let e = &self.elements[ie];
            let lin = self.linear(ie, e, x);
            if lin.force_b.iter().any(|f| !f.is_finite()) {
                return false;
            }
            let k = &at_k[j];
            let (db, da) = (sub(x[e.b], xk[e.b]), sub(x[e.a], xk[e.a]));
            let mut rem_b = [0.0; 3];
            for (c, rb) in rem_b.iter_mut().enumerate() {
                let lin_term: f64 = (0..3).map(|d| k.blk[c][d] * (db[d] - da[d])).sum();
                *rb = w * (lin.force_b[c] - k.force_b[c]) - lin_term;
            }
            // Element j joins chain positions j and j + 1; its force acts +on b, −on a.
            let (pa, pb) = if e.a == self.chain(j) {
                (j, j + 1)
            } else {
                (j + 1, j)
            };
            if let Some(p) = self.interior(pb) {
                for c in 0..3 {
                    r[p][c] += rem_b[c];
                }
            }
            if let Some(p) = self.interior(pa) {
                for c in 0..3 {
                    r[p][c] -= rem_b[c];
                }
            }
            now.push(lin);
        }
        // The seabed's nonlinear remainder (its kink at touchdown and the damping ramp).
        sc.bed_now.clear();
        for (b, &p) in self.bed_nodes.iter().enumerate() {
            let i = line.nodes[p];
            let (q, jz) = self.bed_linear(i, x[i]);
            let (qk, jk) = sc.bed_k[b];
            if !q.is_finite() {
                return false;
            }
            r[p][2] += w * (q - qk) - jk * (x[i][2] - xk[i][2]);
            sc.bed_now.push(jz);
        }
        true
    }

    /// δ (into `sc.delta`) solving (J_ii + J_F(x) − J_F(x^k))·δ = r by block elimination;
    /// false if a pivot block is singular.
    fn newton_correction(&self, sc: &mut Scratch) -> bool {
        let line = self.line;
        let m = line.nodes.len();
        let vals = &self.sys.values;
        let read = |p: usize, s: usize| {
            let b = &line.blocks[p][s];
            Matrix3::from_fn(|i, j| vals[b[3 * i + j]])
        };
        sc.diag.clear();
        sc.lower.clear();
        sc.upper.clear();
        for p in 0..m {
            sc.diag.push(read(p, 1));
            sc.lower
                .push(if p > 0 { read(p, 0) } else { Matrix3::zeros() });
            sc.upper.push(if p + 1 < m {
                read(p, 2)
            } else {
                Matrix3::zeros()
            });
        }
        for j in 0..line.elems.len() {
            let d = Matrix3::from_fn(|a, b| sc.now[j].blk[a][b] - sc.at_k[j].blk[a][b]);
            // Chain positions j and j + 1; the block enters both diagonals with +, and both
            // off-diagonals with − whichever end is a (`assemble_jacobian`).
            let (p0, p1) = (self.interior(j), self.interior(j + 1));
            if let Some(p) = p0 {
                sc.diag[p] += d;
            }
            if let Some(q) = p1 {
                sc.diag[q] += d;
            }
            if let (Some(p), Some(q)) = (p0, p1) {
                sc.upper[p] -= d;
                sc.lower[q] -= d;
            }
        }
        for (b, &p) in self.bed_nodes.iter().enumerate() {
            sc.diag[p][(2, 2)] += sc.bed_now[b] - sc.bed_k[b].1;
        }
        // Block forward elimination and back substitution.
        sc.rhs.clear();
        sc.rhs
            .extend(sc.r.iter().map(|v| Vector3::new(v[0], v[1], v[2])));
        sc.inv.clear();
        for p in 0..m {
            if p > 0 {
                let li = sc.lower[p] * sc.inv[p - 1];
                let u = sc.upper[p - 1];
                sc.diag[p] -= li * u;
                let prev = sc.rhs[p - 1];
                sc.rhs[p] -= li * prev;
            }
            match sc.diag[p].try_inverse() {
                Some(inv) => sc.inv.push(inv),
                None => return false,
            }
        }
        sc.delta.clear();
        sc.delta.resize(m, [0.0; 3]);
        let mut next = Vector3::zeros();
        for p in (0..m).rev() {
            let v = if p + 1 < m {
                sc.inv[p] * (sc.rhs[p] - sc.upper[p] * next)
            } else {
                sc.inv[p] * sc.rhs[p]
            };
            sc.delta[p] = [v[0], v[1], v[2]];
            next = v;
        }
        true
    }
}

fn block_norm(r: &[[f64; 3]]) -> f64 {
    r.iter()
        .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        .sum::<f64>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loads::NoLoads;
    use crate::model::{CableSection, Dofs, Environment, ModelBuilder, UnstretchedLength};

    /// A polyline of `n` segments from `a` to `b`, reusing `first`/`last` when given.
    fn polyline(
        bld: &mut ModelBuilder,
        g: crate::model::GroupId,
        a: [f64; 3],
        b: [f64; 3],
        n: usize,
        first: Option<usize>,
        last: Option<usize>,
    ) -> Vec<usize> {
        let mut nodes = Vec::new();
        for i in 0..=n {
            let s = i as f64 / n as f64;
            let node = match (i, first, last) {
                (0, Some(f), _) => f,
                (i, _, Some(l)) if i == n => l,
                _ => bld
                    .add_node([
                        a[0] + s * (b[0] - a[0]),
                        a[1] + s * (b[1] - a[1]),
                        a[2] + s * (b[2] - a[2]),
                    ])
                    .unwrap(),
            };
            nodes.push(node);
        }
        for w in nodes.windows(2) {
            bld.add_cable(w[0], w[1], g, UnstretchedLength::Given(1.0))
                .unwrap();
        }
        nodes
    }

    /// Three lines meet at a plate; one of them is held half-way; a closed ring hangs apart.
    /// Lines end at the plate, at held nodes and at fixed nodes; the ring has no ends.
    #[test]
    fn lines_end_at_junctions_and_held_nodes_and_rings_are_left_out() {
        let mut b = ModelBuilder::new(Environment::default());
        let g = b.add_group("rope", CableSection::new(1e6, 1.0)).unwrap();
        let plate = b.add_node([0.0, 0.0, 0.0]).unwrap();
        let a = polyline(
            &mut b,
            g,
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            10,
            Some(plate),
            None,
        );
        let c = polyline(
            &mut b,
            g,
            [0.0, 0.0, 0.0],
            [0.0, 8.0, 0.0],
            8,
            Some(plate),
            None,
        );
        let d = polyline(
            &mut b,
            g,
            [0.0, 0.0, 0.0],
            [-6.0, 0.0, 0.0],
            6,
            Some(plate),
            None,
        );
        for end in [a[10], c[8], d[6]] {
            b.fix(end, Dofs::ALL).unwrap();
        }
        // Line c is held in z at its fourth node: that node is an end of two lines.
        b.fix(
            c[4],
            Dofs {
                x: false,
                y: false,
                z: true,
            },
        )
        .unwrap();
        let ring_start = b.add_node([20.0, 0.0, 0.0]).unwrap();
        let mut prev = ring_start;
        for k in 1..6 {
            let t = k as f64 * std::f64::consts::PI / 3.0;
            let n = b.add_node([20.0 + t.cos(), t.sin(), 0.0]).unwrap();
            b.add_cable(prev, n, g, UnstretchedLength::Given(1.0))
                .unwrap();
            prev = n;
        }
        b.add_cable(prev, ring_start, g, UnstretchedLength::Given(1.0))
            .unwrap();
        let model = b.build().unwrap();
        let sys = System::new(&model, &NoLoads).unwrap();
        let lr = LineRelaxation::new(&model, &sys);
        let mut found: Vec<(usize, [usize; 2])> = lr
            .lines
            .iter()
            .map(|l| {
                let mut e = l.ends;
                e.sort();
                (l.nodes.len(), e)
            })
            .collect();
        found.sort();
        let mut expected = vec![
            (9, [plate, a[10]]),
            (3, [plate, c[4]]),
            (3, [c[4], c[8]]),
            (5, [plate, d[6]]),
        ];
        for (_, e) in expected.iter_mut() {
            e.sort();
        }
        expected.sort();
        assert_eq!(found, expected);
        // Every line's elements run from one end to the other through its nodes.
        for l in &lr.lines {
            assert_eq!(l.elems.len(), l.nodes.len() + 1);
            let els = model.elements();
            let joins = |ie: usize, p: usize, q: usize| {
                let e = &els[ie];
                (e.a, e.b) == (p, q) || (e.a, e.b) == (q, p)
            };
            let mut chain = vec![l.ends[0]];
            chain.extend(&l.nodes);
            chain.push(l.ends[1]);
            for (j, w) in chain.windows(2).enumerate() {
                assert!(joins(l.elems[j], w[0], w[1]));
            }
        }
    }
}
