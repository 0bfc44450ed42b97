//! Global system: DOF numbering, sparse pattern (built once), assembly of residual and
//! Jacobian, and the sparse LU with its symbolic factorisation reused
//! (docs/theory/fem.md#sparse-linear-algebra).

use crate::bending::{self, HingeEval};
use crate::cable::{self, CableEval};
use crate::error::{FemError, Result};
use crate::friction::{self, Normal};
use crate::loads::{ElementLoad, LoadProvider, MAX_LOAD_DOFS, MAX_LOAD_NODES, Want};
use crate::model::Model;
use crate::seabed::BedLaw;
use crate::symmetric::{RefineStop, SymmetricSolver};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};
use rayon::prelude::*;

pub(crate) const NONE: usize = usize::MAX;
/// Factorisations on the LU after the symmetric path failed before it is tried again.
const SYMMETRIC_PAUSE: usize = 64;
/// A stale L·D·Lᵀ is replaced when a solve with it needs more than this many refinement
/// sweeps beyond the last solve with a fresh one (a numeric factorisation of the reference
/// cage costs about as much as 7 sweeps).
const STALE_EXTRA_SWEEPS: usize = 4;
/// Element count from which element kernels run in parallel (docs/theory/fem.md#threads).
const PAR_THRESHOLD: usize = 512;

/// Jacobian coefficients: J = m·M + k·K + c·C with K = ∂q/∂x, C = ∂q/∂v.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Coef {
    pub m: f64,
    pub k: f64,
    pub c: f64,
}

/// What to evaluate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EvalOptions {
    pub t: f64,
    /// Scale of gravity, point forces and water loads (load continuation).
    pub load_scale: f64,
    /// Velocity-dependent terms (axial, seabed and Rayleigh damping) active.
    pub dynamic: bool,
    pub jacobian: Option<Coef>,
    /// Compute M·a into `ma`.
    pub inertia: bool,
    pub consistent_mass: bool,
    /// Rayleigh damping (a_M, a_K).
    pub rayleigh: (f64, f64),
    /// Form a missing ∂f_h/∂x by finite differences (otherwise it is omitted).
    pub fd_dfdx: bool,
    /// Use max(T, 0) in the geometric stiffness (robust tangent for slack-dominated states).
    pub clamp_geometric: bool,
}

/// Sparse LU with a symbolic factorisation computed once.
struct LinearSolver {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinearSolver").finish_non_exhaustive()
    }
}

/// The positions at the start and end of a step.
pub(crate) type StepEnds = (Vec<[f64; 3]>, Vec<[f64; 3]>);

#[derive(Debug)]
pub(crate) struct System {
    pub n_nodes: usize,
    /// Free index of global DOF 3i+k, or NONE.
    pub free_of_dof: Vec<usize>,
    /// Global DOF of each free index.
    pub dof_of_free: Vec<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    pub values: Vec<f64>,
    cable_pos: Vec<[usize; 36]>,
    hinge_pos: Vec<[usize; 81]>,
    node_pos: Vec<[usize; 9]>,
    load_nodes: Vec<[usize; MAX_LOAD_NODES]>,
    load_nn: Vec<usize>,
    load_pos_off: Vec<usize>,
    load_pos: Vec<usize>,
    load_stride: usize,
    load_buf: Vec<f64>,
    /// Per-element results of the last evaluation.
    pub cable: Vec<CableEval>,
    /// Per-hinge results of the last evaluation (energy, force, tangent when a Jacobian was
    /// asked for).
    pub hinge: Vec<HingeEval>,
    /// Internal (elastic + axial damping + Rayleigh) force, q sense [N].
    pub fint: Vec<[f64; 3]>,
    /// External forces on the structure: gravity, point forces, water loads, seabed [N].
    pub fext: Vec<[f64; 3]>,
    /// Water loads from the provider [N].
    pub fhydro: Vec<[f64; 3]>,
    /// Seabed contact force [N].
    pub fbed: Vec<[f64; 3]>,
    /// −∂f_bed,z/∂z of the last evaluation (2·∂/∂z1 for the midpoint rule) [N/m].
    bed_kz: Vec<f64>,
    /// −∂f_bed,z/∂v_z of the last evaluation [N·s/m].
    bed_cz: Vec<f64>,
    /// Cable elements at each node for the friction's line direction: up to two, `NONE`
    /// padded; `None` for a junction of three or more (docs/theory/fem.md#seabed-friction).
    node_lines: Vec<Option<[usize; 2]>>,
    /// Seabed friction of the last evaluation: −∂f/∂x and −∂f/∂v per node (rows x, y).
    fric_k: Vec<[[f64; 3]; 3]>,
    fric_c: Vec<[[f64; 3]; 3]>,
    /// Friction damping μN/v_c outside the linear zone per node (explicit stable step) [N·s/m].
    fric_spare: Vec<f64>,
    /// Friction acted in the last evaluation.
    friction_on: bool,
    /// q = f_int − f_ext [N].
    pub q: Vec<[f64; 3]>,
    /// M·a (structural + added mass) [N].
    pub ma: Vec<[f64; 3]>,
    mv: Vec<[f64; 3]>,
    /// Added-mass blocks per node [kg].
    pub added: Vec<[[f64; 3]; 3]>,
    /// Position of the diagonal entry of each free DOF in `values`.
    pub diag_pos: Vec<usize>,
    solver: Option<LinearSolver>,
    pub n_factorisations: usize,
    /// Factorise the symmetric part as L·D·Lᵀ and refine on the rest (dynamics), with the LU
    /// as fallback (docs/theory/fem.md#sparse-linear-algebra).
    pub symmetric: bool,
    pub(crate) sym: Option<SymmetricSolver>,
    /// The last factorisation is the symmetric one.
    sym_active: bool,
    /// Factorisations left on the LU after a symmetric fallback.
    sym_pause: usize,
    /// The pattern is not structurally symmetric: LU only.
    sym_unusable: bool,
    /// Solves that fell back from the symmetric factor to the LU.
    pub n_symmetric_fallbacks: usize,
    /// Refinement sweeps of all symmetric solves.
    pub n_refinement_sweeps: usize,
    /// Symmetric solves that kept an earlier L·D·Lᵀ as the preconditioner.
    pub n_factor_reuses: usize,
    /// The next `factorize` must factorise afresh (no usable L·D·Lᵀ, or the last one has
    /// grown too stale).
    sym_refactor: bool,
    /// Refinement sweeps of the last solve with a fresh L·D·Lᵀ.
    sym_fresh_sweeps: usize,
    load_scratch: (Box<ElementLoad>, Box<ElementLoad>),
    /// When set, the cables' elastic force is the discrete gradient between these start and
    /// end positions of the step (docs/theory/fem.md#energy-consistent-midpoint), evaluated
    /// in the configuration passed to `evaluate` (the midpoint).
    pub secant: Option<StepEnds>,
}

fn pos_in(col_ptr: &[usize], row_idx: &[usize], row: usize, col: usize) -> usize {
    let s = &row_idx[col_ptr[col]..col_ptr[col + 1]];
    col_ptr[col] + s.binary_search(&row).expect("entry in pattern")
}

impl System {
    /// Numbers the free DOFs and builds the sparse pattern of the free-DOF Jacobian.
    pub fn new<P: LoadProvider + ?Sized>(model: &Model, provider: &P) -> Result<Self> {
        let n = model.n_nodes();
        let mut free_of_dof = vec![NONE; 3 * n];
        let mut dof_of_free = Vec::new();
        for i in 0..n {
            for k in 0..3 {
                if !model.is_constrained(i, k) {
                    free_of_dof[3 * i + k] = dof_of_free.len();
                    dof_of_free.push(3 * i + k);
                }
            }
        }
        let nl = provider.n_elements();
        let mut load_nodes = Vec::with_capacity(nl);
        let mut load_nn = Vec::with_capacity(nl);
        let mut max_nn = 0;
        for e in 0..nl {
            let nodes = provider.element_nodes(e);
            if nodes.is_empty() || nodes.len() > MAX_LOAD_NODES {
                return Err(FemError::Load {
                    element: e,
                    message: format!(
                        "load element has {} nodes; 1 to {MAX_LOAD_NODES} are allowed",
                        nodes.len()
                    ),
                });
            }
            let mut arr = [0; MAX_LOAD_NODES];
            for (j, &nd) in nodes.iter().enumerate() {
                if nd >= n {
                    return Err(FemError::UnknownNode {
                        what: format!("load element {e}"),
                        node: nd,
                        n_nodes: n,
                    });
                }
                if nodes[..j].contains(&nd) {
                    return Err(FemError::Load {
                        element: e,
                        message: format!("node {nd} listed twice"),
                    });
                }
                arr[j] = nd;
            }
            max_nn = max_nn.max(nodes.len());
            load_nodes.push(arr);
            load_nn.push(nodes.len());
        }
        // Node adjacency (sorted, deduplicated), including self.
        let mut adj: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
        for e in model.elements() {
            adj[e.a].push(e.b);
            adj[e.b].push(e.a);
        }
        for h in model.hinges() {
            for &p in &h.nodes {
                adj[p].extend(h.nodes.iter().filter(|&&q| q != p));
            }
        }
        for (e, nodes) in load_nodes.iter().enumerate() {
            let nn = load_nn[e];
            for &p in &nodes[..nn] {
                for &q in &nodes[..nn] {
                    if p != q {
                        adj[p].push(q);
                    }
                }
            }
        }
        for a in &mut adj {
            a.sort_unstable();
            a.dedup();
        }
        // CSC pattern over free DOFs; column order follows global DOF order, so rows sorted.
        let nf = dof_of_free.len();
        let mut col_ptr = Vec::with_capacity(nf + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for &gd in &dof_of_free {
            let node = gd / 3;
            for &nb in &adj[node] {
                for k in 0..3 {
                    let f = free_of_dof[3 * nb + k];
                    if f != NONE {
                        row_idx.push(f);
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pos = |ni: usize, ki: usize, nj: usize, kj: usize| -> usize {
            let r = free_of_dof[3 * ni + ki];
            let c = free_of_dof[3 * nj + kj];
            if r == NONE || c == NONE {
                NONE
            } else {
                pos_in(&col_ptr, &row_idx, r, c)
            }
        };
        let mut cable_pos = Vec::with_capacity(model.elements().len());
        for e in model.elements() {
            let nodes = [e.a, e.b];
            let mut p = [NONE; 36];
            for i in 0..2 {
                for ki in 0..3 {
                    for j in 0..2 {
                        for kj in 0..3 {
                            p[(3 * i + ki) * 6 + 3 * j + kj] = pos(nodes[i], ki, nodes[j], kj);
                        }
                    }
                }
            }
            cable_pos.push(p);
        }
        let mut hinge_pos = Vec::with_capacity(model.hinges().len());
        for h in model.hinges() {
            let mut p = [NONE; 81];
            for (i, &ni) in h.nodes.iter().enumerate() {
                for (j, &nj) in h.nodes.iter().enumerate() {
                    for ki in 0..3 {
                        for kj in 0..3 {
                            p[(3 * i + ki) * 9 + 3 * j + kj] = pos(ni, ki, nj, kj);
                        }
                    }
                }
            }
            hinge_pos.push(p);
        }
        let mut node_pos = Vec::with_capacity(n);
        for i in 0..n {
            let mut p = [NONE; 9];
            for ki in 0..3 {
                for kj in 0..3 {
                    p[3 * ki + kj] = pos(i, ki, i, kj);
                }
            }
            node_pos.push(p);
        }
        let mut load_pos_off = Vec::with_capacity(nl + 1);
        let mut load_pos = Vec::new();
        load_pos_off.push(0);
        for (e, nodes) in load_nodes.iter().enumerate() {
            let nn = load_nn[e];
            for i in 0..nn {
                for ki in 0..3 {
                    for j in 0..nn {
                        for kj in 0..3 {
                            load_pos.push(pos(nodes[i], ki, nodes[j], kj));
                        }
                    }
                }
            }
            load_pos_off.push(load_pos.len());
        }
        let diag_pos = (0..nf).map(|f| pos_in(&col_ptr, &row_idx, f, f)).collect();
        let mut node_lines = vec![Some([NONE; 2]); n];
        for (ie, e) in model.elements().iter().enumerate() {
            for nd in [e.a, e.b] {
                node_lines[nd] = match node_lines[nd] {
                    Some([NONE, _]) => Some([ie, NONE]),
                    Some([f, NONE]) => Some([f, ie]),
                    _ => None,
                };
            }
        }
        let load_stride = 12 * max_nn + 9 * max_nn * max_nn;
        let nnz = row_idx.len();
        Ok(Self {
            n_nodes: n,
            free_of_dof,
            dof_of_free,
            col_ptr,
            row_idx,
            values: vec![0.0; nnz],
            cable_pos,
            hinge_pos,
            node_pos,
            load_nodes,
            load_nn,
            load_pos_off,
            load_pos,
            load_stride,
            load_buf: vec![0.0; load_stride * nl],
            cable: vec![CableEval::default(); model.elements().len()],
            hinge: vec![HingeEval::default(); model.hinges().len()],
            fint: vec![[0.0; 3]; n],
            fext: vec![[0.0; 3]; n],
            fhydro: vec![[0.0; 3]; n],
            fbed: vec![[0.0; 3]; n],
            bed_kz: vec![0.0; n],
            bed_cz: vec![0.0; n],
            node_lines,
            fric_k: vec![[[0.0; 3]; 3]; n],
            fric_c: vec![[[0.0; 3]; 3]; n],
            fric_spare: vec![0.0; n],
            friction_on: false,
            q: vec![[0.0; 3]; n],
            ma: vec![[0.0; 3]; n],
            mv: vec![[0.0; 3]; n],
            added: vec![[[0.0; 3]; 3]; n],
            diag_pos,
            solver: None,
            n_factorisations: 0,
            symmetric: false,
            sym: None,
            sym_active: false,
            sym_pause: 0,
            sym_unusable: false,
            n_symmetric_fallbacks: 0,
            n_factor_reuses: 0,
            sym_refactor: true,
            sym_fresh_sweeps: 0,
            n_refinement_sweeps: 0,
            load_scratch: Default::default(),
            secant: None,
        })
    }

    /// Position in `values` of the Jacobian entry (free row, free column), if in the pattern.
    pub(crate) fn entry_pos(&self, row: usize, col: usize) -> Option<usize> {
        if row == NONE || col == NONE {
            return None;
        }
        let s = &self.row_idx[self.col_ptr[col]..self.col_ptr[col + 1]];
        s.binary_search(&row).ok().map(|k| self.col_ptr[col] + k)
    }

    /// The nodes of each load element.
    pub(crate) fn load_element_nodes(&self) -> impl Iterator<Item = &[usize]> {
        self.load_nodes
            .iter()
            .zip(&self.load_nn)
            .map(|(nodes, &nn)| &nodes[..nn])
    }

    /// Number of free DOFs.
    pub fn n_free(&self) -> usize {
        self.dof_of_free.len()
    }

    /// Row sums of |J| (free DOFs) of the last assembled Jacobian.
    pub fn row_abs_sums(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.n_free()];
        for c in 0..self.n_free() {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                out[self.row_idx[p]] += self.values[p].abs();
            }
        }
        out
    }

    /// Evaluates forces (and optionally M·a and the Jacobian) at state (x, v, a).
    pub fn evaluate<P: LoadProvider + ?Sized>(
        &mut self,
        model: &Model,
        provider: &mut P,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        a: &[[f64; 3]],
        o: &EvalOptions,
    ) -> Result<()> {
        let n = self.n_nodes;
        provider.prepare(o.t, x, v).map_err(|e| FemError::Load {
            element: usize::MAX,
            message: e.0,
        })?;
        // Cable elements.
        let elements = model.elements();
        let damping = o.dynamic;
        let a_k = if o.dynamic { o.rayleigh.1 } else { 0.0 };
        let clamp = o.clamp_geometric;
        let secant = self.secant.as_ref();
        let kernel = |(i, out): (usize, &mut CableEval)| {
            let e = &elements[i];
            *out = cable::evaluate(
                e,
                x[e.a],
                x[e.b],
                v[e.a],
                v[e.b],
                damping,
                a_k * e.ea,
                clamp,
            );
            if let Some((x0, x1)) = secant {
                let l0 = norm(sub(x0[e.b], x0[e.a]));
                cable::use_secant_tension(e, l0, sub(x1[e.b], x1[e.a]), out);
            }
        };
        if elements.len() >= PAR_THRESHOLD {
            self.cable.par_iter_mut().enumerate().for_each(kernel);
        } else {
            self.cable.iter_mut().enumerate().for_each(kernel);
        }
        if let Some(i) = self.cable.iter().position(|c| c.bad) {
            let e = &elements[i];
            return Err(FemError::NonFinite(format!(
                "element {i} (nodes {}-{}): length {:.3e} m (L0 = {:.3e} m) degenerate or non-finite",
                e.a, e.b, self.cable[i].length, e.l0
            )));
        }
        self.evaluate_hinges(model, x, o.jacobian.is_some())?;
        // Load elements.
        let nl = self.load_nn.len();
        if nl > 0 {
            let stride = self.load_stride;
            let want = Want {
                dfdv: o.jacobian.is_some_and(|c| c.c != 0.0) && o.dynamic,
                dfdx: o.jacobian.is_some_and(|c| c.k != 0.0),
            };
            let coef = o.jacobian.unwrap_or(Coef {
                m: 0.0,
                k: 0.0,
                c: 0.0,
            });
            let scale = o.load_scale;
            let fd_dfdx = o.fd_dfdx;
            let t = o.t;
            let (load_nodes, load_nn) = (&self.load_nodes, &self.load_nn);
            let prov: &P = provider;
            let kernel = |bufs: &mut (Box<ElementLoad>, Box<ElementLoad>),
                          (e, chunk): (usize, &mut [f64])|
             -> Result<()> {
                let nn = load_nn[e];
                let mut xl = [[0.0; 3]; MAX_LOAD_NODES];
                let mut vl = [[0.0; 3]; MAX_LOAD_NODES];
                for j in 0..nn {
                    xl[j] = x[load_nodes[e][j]];
                    vl[j] = v[load_nodes[e][j]];
                }
                let (out, tmp) = bufs;
                load_element(
                    prov, e, nn, t, &xl, &vl, want, coef, scale, fd_dfdx, chunk, out, tmp,
                )
            };
            let res: Result<()> = if nl >= PAR_THRESHOLD {
                self.load_buf
                    .par_chunks_mut(stride)
                    .enumerate()
                    .try_for_each_init(
                        || (Box::<ElementLoad>::default(), Box::<ElementLoad>::default()),
                        kernel,
                    )
            } else {
                let mut bufs = std::mem::take(&mut self.load_scratch);
                let r = self
                    .load_buf
                    .chunks_mut(stride)
                    .enumerate()
                    .try_for_each(|item| kernel(&mut bufs, item));
                self.load_scratch = bufs;
                r
            };
            res?;
        }
        // Nodal assembly.
        let g_scale = o.load_scale;
        for i in 0..n {
            self.fint[i] = [0.0; 3];
            self.fhydro[i] = [0.0; 3];
            self.fbed[i] = [0.0; 3];
            self.added[i] = [[0.0; 3]; 3];
        }
        for (e, c) in elements.iter().zip(&self.cable) {
            for k in 0..3 {
                self.fint[e.a][k] -= c.force_b[k];
                self.fint[e.b][k] += c.force_b[k];
            }
        }
        for (h, ev) in model.hinges().iter().zip(&self.hinge) {
            for (&nd, f) in h.nodes.iter().zip(&ev.force) {
                for k in 0..3 {
                    self.fint[nd][k] += f[k];
                }
            }
        }
        for e in 0..nl {
            let nn = self.load_nn[e];
            let chunk = &self.load_buf[e * self.load_stride..];
            for j in 0..nn {
                let nd = self.load_nodes[e][j];
                for k in 0..3 {
                    self.fhydro[nd][k] += g_scale * chunk[3 * j + k];
                    for l in 0..3 {
                        self.added[nd][k][l] += chunk[3 * nn + 9 * j + 3 * k + l];
                    }
                }
            }
        }
        // Seabed.
        let bed = BedLaw::new(model, o.dynamic);
        let secant = self.secant.as_ref();
        for i in 0..n {
            let ends = secant.map(|(x0, x1)| (x0[i][2], x1[i][2]));
            let (f, kz, cz) = bed.node(model, i, x[i][2], v[i][2], ends);
            self.fbed[i][2] += f;
            self.bed_kz[i] = kz;
            self.bed_cz[i] = cz;
        }
        self.seabed_friction(model, x, v, o.dynamic);
        let a_m = if o.dynamic { o.rayleigh.0 } else { 0.0 };
        for i in 0..n {
            for k in 0..3 {
                self.fext[i][k] = g_scale * (model.weight[i][k] + model.point_force[i][k])
                    + self.fhydro[i][k]
                    + self.fbed[i][k];
            }
        }
        // Structural mass products (M·a and Rayleigh a_M·M·v).
        let need_ma = o.inertia;
        if need_ma || a_m != 0.0 {
            for i in 0..n {
                self.ma[i] = [0.0; 3];
            }
            if a_m != 0.0 {
                mul_mass(model, o.consistent_mass, v, &mut self.mv);
                for i in 0..n {
                    for k in 0..3 {
                        self.fint[i][k] += a_m * self.mv[i][k];
                    }
                }
            }
            if need_ma {
                mul_mass(model, o.consistent_mass, a, &mut self.mv);
                for i in 0..n {
                    for k in 0..3 {
                        let mut s = self.mv[i][k];
                        for l in 0..3 {
                            s += self.added[i][k][l] * a[i][l];
                        }
                        self.ma[i][k] = s;
                    }
                }
            }
        }
        for i in 0..n {
            for k in 0..3 {
                self.q[i][k] = self.fint[i][k] - self.fext[i][k];
            }
        }
        if let Some(cf) = o.jacobian {
            self.assemble_jacobian(model, cf, o, a_m);
        }
        Ok(())
    }

    fn assemble_jacobian(&mut self, model: &Model, cf: Coef, o: &EvalOptions, a_m: f64) {
        let vals = &mut self.values;
        vals.iter_mut().for_each(|x| *x = 0.0);
        let mass_c = cf.m + cf.c * a_m;
        for (ie, (e, c)) in model.elements().iter().zip(&self.cable).enumerate() {
            let p = &self.cable_pos[ie];
            let mut blk = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    blk[i][j] = cf.k * c.k[i][j] + cf.c * c.c[i][j];
                }
            }
            let mm = if o.consistent_mass && mass_c != 0.0 {
                mass_c * e.mu * e.l0 / 6.0
            } else {
                0.0
            };
            for i in 0..2 {
                for j in 0..2 {
                    let sign = if i == j { 1.0 } else { -1.0 };
                    let mdiag = if i == j { 2.0 * mm } else { mm };
                    for ki in 0..3 {
                        for kj in 0..3 {
                            let pp = p[(3 * i + ki) * 6 + 3 * j + kj];
                            if pp != NONE {
                                let mut val = sign * blk[ki][kj];
                                if ki == kj {
                                    val += mdiag;
                                }
                                vals[pp] += val;
                            }
                        }
                    }
                }
            }
        }
        // Bending hinges (docs/theory/fem.md#bending).
        if cf.k != 0.0 {
            for (p, ev) in self.hinge_pos.iter().zip(&self.hinge) {
                for (r, row) in ev.k.iter().enumerate() {
                    for (c, &kv) in row.iter().enumerate() {
                        let pp = p[9 * r + c];
                        if pp != NONE {
                            vals[pp] += cf.k * kv;
                        }
                    }
                }
            }
        }
        // Node blocks: lumped/point mass, added mass, seabed.
        for i in 0..self.n_nodes {
            let p = &self.node_pos[i];
            if p.iter().all(|&q| q == NONE) {
                continue;
            }
            let m_struct = if o.consistent_mass {
                model.point_mass_at(i)
            } else {
                model.lumped_mass[i]
            };
            for ki in 0..3 {
                for kj in 0..3 {
                    let pp = p[3 * ki + kj];
                    if pp == NONE {
                        continue;
                    }
                    let mut val = cf.m * self.added[i][ki][kj];
                    if ki == kj {
                        val += mass_c * m_struct;
                    }
                    vals[pp] += val;
                }
            }
            let pz = p[8];
            if pz != NONE {
                vals[pz] += cf.k * self.bed_kz[i] + cf.c * self.bed_cz[i];
            }
            if self.friction_on {
                let (fk, fc) = (&self.fric_k[i], &self.fric_c[i]);
                for ki in 0..2 {
                    for kj in 0..3 {
                        let pp = p[3 * ki + kj];
                        if pp != NONE {
                            vals[pp] += cf.k * fk[ki][kj] + cf.c * fc[ki][kj];
                        }
                    }
                }
            }
        }
        // Load elements: stored block is already −scale·(k·dfdx + c·dfdv).
        for e in 0..self.load_nn.len() {
            let nn = self.load_nn[e];
            let nd = 3 * nn;
            let chunk = &self.load_buf[e * self.load_stride + 12 * nn..];
            let pos = &self.load_pos[self.load_pos_off[e]..self.load_pos_off[e + 1]];
            for (r, &pp) in pos.iter().enumerate() {
                if pp != NONE {
                    vals[pp] += chunk[r];
                }
            }
            debug_assert_eq!(pos.len(), nd * nd);
        }
    }

    /// Regularised Coulomb friction of the nodes in contact (dynamics only), from the normal
    /// force N = f_bed,z just formed, added to `fbed` (docs/theory/fem.md#seabed-friction).
    fn seabed_friction(&mut self, model: &Model, x: &[[f64; 3]], v: &[[f64; 3]], dynamic: bool) {
        let params = match model.env.seabed {
            Some(s) if dynamic && s.friction.is_active() => s.friction,
            _ => {
                if self.friction_on {
                    self.fric_spare.iter_mut().for_each(|c| *c = 0.0);
                }
                self.friction_on = false;
                return;
            }
        };
        self.friction_on = true;
        let elements = model.elements();
        for i in 0..self.n_nodes {
            let n = Normal {
                force: self.fbed[i][2],
                kz: self.bed_kz[i],
                cz: self.bed_cz[i],
            };
            if !(n.force > 0.0) {
                self.fric_k[i] = [[0.0; 3]; 3];
                self.fric_c[i] = [[0.0; 3]; 3];
                self.fric_spare[i] = 0.0;
                continue;
            }
            let axis = self.node_lines[i].and_then(|lines| {
                let mut dirs = [[0.0; 3]; 2];
                let mut m = 0;
                for &ie in lines.iter().filter(|&&ie| ie != NONE) {
                    let e = &elements[ie];
                    let d = sub(x[e.b], x[e.a]);
                    let l = norm(d);
                    if l > 0.0 {
                        dirs[m] = [d[0] / l, d[1] / l, d[2] / l];
                        m += 1;
                    }
                }
                friction::line_axis(&dirs[..m])
            });
            let nf = friction::node_friction(&params, n, v[i], axis);
            self.fbed[i][0] += nf.force[0];
            self.fbed[i][1] += nf.force[1];
            self.fric_k[i] = nf.k;
            self.fric_c[i] = nf.c;
            self.fric_spare[i] = nf.spare_c;
        }
    }

    /// Seabed friction damping μN/v_c that the last evaluation's Jacobian left out at node
    /// `i` because the node slid faster than v_c (it returns when the node slows down) [N·s/m].
    pub fn friction_spare_damping(&self, i: usize) -> f64 {
        self.fric_spare[i]
    }

    /// Evaluates the bending hinges at `x` (docs/theory/fem.md#bending); in the energy-consistent
    /// midpoint rule they are evaluated at the midpoint like everything else (no discrete
    /// gradient for bending).
    fn evaluate_hinges(&mut self, model: &Model, x: &[[f64; 3]], tangent: bool) -> Result<()> {
        let hinges = model.hinges();
        let kernel = |(h, out): (&bending::Hinge, &mut HingeEval)| {
            let [a, b, c] = h.nodes;
            bending::evaluate(h, x[a], x[b], x[c], tangent, out);
        };
        if hinges.len() >= PAR_THRESHOLD {
            hinges
                .par_iter()
                .zip(self.hinge.par_iter_mut())
                .for_each(kernel);
        } else {
            hinges.iter().zip(self.hinge.iter_mut()).for_each(kernel);
        }
        if let Some(i) = self.hinge.iter().position(|h| h.bad) {
            let [a, b, c] = hinges[i].nodes;
            return Err(FemError::NonFinite(format!(
                "bending hinge {i} (nodes {a}-{b}-{c}): an edge has zero length, the edges fold \
                 back onto each other, or the bending force is non-finite"
            )));
        }
        Ok(())
    }

    /// Total bending energy Σ W of the hinges at the last evaluation [J].
    pub fn bending_energy(&self) -> f64 {
        self.hinge.iter().map(|h| h.energy).sum()
    }

    /// Per node, the largest row sum of |∂²W/∂x²| of the hinges (Gershgorin bound of the
    /// bending stiffness) at the last evaluation with a Jacobian [N/m], added into `out`.
    pub fn add_hinge_row_sums(&self, model: &Model, out: &mut [f64]) {
        for (h, ev) in model.hinges().iter().zip(&self.hinge) {
            for (i, &nd) in h.nodes.iter().enumerate() {
                let m = (0..3)
                    .map(|k| ev.k[3 * i + k].iter().map(|v| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                out[nd] += m;
            }
        }
    }

    /// Factorises the current `values`: the symmetric L·D·Lᵀ with refinement when `symmetric`
    /// is set and it applies, else the sparse LU (symbolic analyses on first use).
    pub fn factorize(&mut self) -> Result<()> {
        let nf = self.n_free();
        if nf == 0 {
            return Ok(());
        }
        if let Some(v) = self.values.iter().find(|v| !v.is_finite()) {
            return Err(FemError::NonFinite(format!("Jacobian entry {v}")));
        }
        self.sym_active = false;
        if self.symmetric && !self.sym_unusable {
            if self.sym_pause > 0 {
                self.sym_pause -= 1;
            } else {
                if self.sym.is_none() {
                    // A failed symbolic analysis leaves the LU, which has its own errors.
                    self.sym =
                        SymmetricSolver::new(nf, &self.col_ptr, &self.row_idx).unwrap_or(None);
                    self.sym_unusable = self.sym.is_none();
                }
                if let Some(s) = self.sym.as_mut() {
                    if !self.sym_refactor {
                        // The last L·D·Lᵀ stays the preconditioner; the refinement solves
                        // with this J (docs/theory/fem.md#sparse-linear-algebra).
                        s.set_matrix(&self.values);
                        self.sym_active = true;
                        self.n_factor_reuses += 1;
                        return Ok(());
                    }
                    if s.factorize(&self.values).is_ok() {
                        self.sym_active = true;
                        self.sym_refactor = false;
                        self.n_factorisations += 1;
                        return Ok(());
                    }
                    self.symmetric_fallback();
                }
            }
        }
        self.factorize_lu(None)
    }

    /// The next `factorize` factorises afresh instead of keeping an earlier L·D·Lᵀ.
    pub fn require_fresh_factor(&mut self) {
        self.sym_refactor = true;
    }

    /// After the symmetric path failed: LU for the next `SYMMETRIC_PAUSE` factorisations.
    fn symmetric_fallback(&mut self) {
        self.n_symmetric_fallbacks += 1;
        self.sym_pause = SYMMETRIC_PAUSE;
        self.sym_active = false;
        self.sym_refactor = true;
    }

    /// The symmetric solve of `rhs` with the current factor; a stale factor that does not
    /// contract is replaced by a fresh one of this J and the solve repeated. `Err` leaves `rhs`
    /// untouched (the caller falls back to the LU).
    /// `floor` and `bound` as in `solve_within`; `Ok(true)` is an early stop on `bound`,
    /// whose sweep count says nothing of the factor's quality and is left out of the
    /// refactor rule.
    fn solve_symmetric(
        &mut self,
        rhs: &mut [f64],
        floor: f64,
        bound: Option<f64>,
    ) -> std::result::Result<bool, ()> {
        let sym = self.sym.as_mut().expect("symmetric factor");
        for _ in 0..2 {
            let fresh = sym.is_fresh();
            let stop = RefineStop { floor, bound };
            let out = sym.solve_within(&self.col_ptr, &self.row_idx, rhs, stop);
            self.n_refinement_sweeps += sym.last_sweeps;
            match (out, fresh) {
                (Ok(true), _) => return Ok(true),
                (Ok(false), true) => {
                    self.sym_fresh_sweeps = sym.last_sweeps;
                    return Ok(false);
                }
                (Ok(false), false) => {
                    // Refactorise once the stale factor costs more sweeps than a new one.
                    if sym.last_sweeps > self.sym_fresh_sweeps + STALE_EXTRA_SWEEPS {
                        self.sym_refactor = true;
                    }
                    return Ok(false);
                }
                (Err(_), true) => return Err(()),
                (Err(_), false) => {
                    self.n_factor_reuses -= 1;
                    if sym.refactor().is_err() {
                        return Err(());
                    }
                    self.n_factorisations += 1;
                    self.sym_refactor = false;
                }
            }
        }
        Err(())
    }

    /// Numeric LU of `values` (the current `self.values` if `None`).
    fn factorize_lu(&mut self, values: Option<&[f64]>) -> Result<()> {
        let nf = self.n_free();
        // SAFETY-free: the pattern was built with sorted, in-range, unique row indices.
        let sym = SymbolicSparseColMatRef::new_checked(nf, nf, &self.col_ptr, None, &self.row_idx);
        if self.solver.is_none() {
            let symbolic = factorize_symbolic_lu(sym, Default::default())
                .map_err(|e| FemError::Linear(format!("symbolic LU: {e:?}")))?;
            let par = Par::Seq;
            let req = symbolic
                .factorize_numeric_lu_scratch::<f64>(par, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, par));
            self.solver = Some(LinearSolver {
                symbolic,
                numeric: NumericLu::new(),
                mem: MemBuffer::try_new(req)
                    .map_err(|_| FemError::Linear("out of memory for LU workspace".into()))?,
            });
        }
        let s = self.solver.as_mut().expect("solver initialised");
        let mat = SparseColMatRef::new(sym, values.unwrap_or(&self.values));
        s.symbolic
            .factorize_numeric_lu(
                &mut s.numeric,
                mat,
                Par::Seq,
                MemStack::new(&mut s.mem),
                Default::default(),
            )
            .map_err(|e| FemError::Linear(format!("singular Jacobian ({e:?}); check supports")))?;
        self.n_factorisations += 1;
        Ok(())
    }

    /// Solves J·y = rhs in place with the last factorisation.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<()> {
        self.solve_within(rhs, 0.0, None).map(|_| ())
    }

    /// As `solve`, for a Newton caller that needs less than the full solution: the
    /// symmetric refinement also stops once ‖rhs − J·y‖₂ ≤ `floor`, and, with `bound`, once
    /// ‖y‖∞ ≤ bound is certain (a convergence check whose update is not applied; `Ok(true)`
    /// then, `rhs` holding the inexact y). `Ok(false)`: `rhs` holds y to 1e-10 or to
    /// `floor`. The LU solve is always exact.
    pub fn solve_within(
        &mut self,
        rhs: &mut [f64],
        floor: f64,
        bound: Option<f64>,
    ) -> Result<bool> {
        let nf = self.n_free();
        if nf == 0 {
            return Ok(false);
        }
        if self.sym_active {
            if let Ok(early) = self.solve_symmetric(rhs, floor, bound) {
                return Ok(early);
            }
            // The LU of the same matrix the symmetric factor was made of.
            let factored = std::mem::take(&mut self.sym.as_mut().expect("symmetric").factored);
            let lu = self.factorize_lu(Some(&factored));
            self.sym.as_mut().expect("symmetric").factored = factored;
            self.symmetric_fallback();
            lu?;
        }
        let s = self
            .solver
            .as_mut()
            .ok_or_else(|| FemError::Linear("solve before factorisation".into()))?;
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&s.symbolic, &s.numeric);
        let m = MatMut::from_column_major_slice_mut(rhs, nf, 1);
        lu.solve_in_place_with_conj(Conj::No, m, Par::Seq, MemStack::new(&mut s.mem));
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(FemError::Linear(
                "the Jacobian is singular (non-finite solution): a part of the structure may be \
                 unsupported or massless"
                    .into(),
            ));
        }
        Ok(false)
    }
}

/// Structural mass matrix (lumped or consistent, plus point masses) times a nodal vector.
pub(crate) fn mul_mass(model: &Model, consistent: bool, a: &[[f64; 3]], out: &mut [[f64; 3]]) {
    let n = model.n_nodes();
    if consistent {
        for i in 0..n {
            let m = model.point_mass_at(i);
            for k in 0..3 {
                out[i][k] = m * a[i][k];
            }
        }
        for e in model.elements() {
            let m = e.mu * e.l0 / 6.0;
            for k in 0..3 {
                out[e.a][k] += m * (2.0 * a[e.a][k] + a[e.b][k]);
                out[e.b][k] += m * (a[e.a][k] + 2.0 * a[e.b][k]);
            }
        }
    } else {
        for i in 0..n {
            let m = model.lumped_mass[i];
            for k in 0..3 {
                out[i][k] = m * a[i][k];
            }
        }
    }
}

/// Evaluates one load element into its buffer chunk: [force 3n][added mass 9n][J (3n)²] with
/// J = −scale·(c_k·∂f/∂x + c_c·∂f/∂v).
#[allow(clippy::too_many_arguments)]
fn load_element<P: LoadProvider + ?Sized>(
    prov: &P,
    e: usize,
    nn: usize,
    t: f64,
    xl: &[[f64; 3]; MAX_LOAD_NODES],
    vl: &[[f64; 3]; MAX_LOAD_NODES],
    want: Want,
    coef: Coef,
    scale: f64,
    fd_dfdx: bool,
    chunk: &mut [f64],
    out: &mut ElementLoad,
    tmp: &mut ElementLoad,
) -> Result<()> {
    let err = |m: crate::error::LoadError| FemError::Load {
        element: e,
        message: m.0,
    };
    out.reset(nn);
    prov.element_load(e, t, &xl[..nn], &vl[..nn], want, out)
        .map_err(err)?;
    let nd = 3 * nn;
    for j in 0..nn {
        for k in 0..3 {
            let f = out.force[j][k];
            if !f.is_finite() {
                return Err(FemError::Load {
                    element: e,
                    message: format!("non-finite force {f} on local node {j}"),
                });
            }
            chunk[3 * j + k] = f;
            for l in 0..3 {
                chunk[3 * nn + 9 * j + 3 * k + l] = out.added_mass[j][k][l];
            }
        }
    }
    if !(want.dfdv || want.dfdx) {
        return Ok(());
    }
    let jac = &mut chunk[12 * nn..12 * nn + nd * nd];
    jac.iter_mut().for_each(|v| *v = 0.0);
    // Element size and speed for the perturbations.
    let mut size: f64 = 0.0;
    let mut speed: f64 = 0.0;
    for i in 0..nn {
        speed = speed.max(norm(vl[i]));
        for j in 0..i {
            size = size.max(norm(sub(xl[i], xl[j])));
        }
    }
    let mut fd = |wrt_x: bool, w: f64, jac: &mut [f64]| -> Result<()> {
        let h = if wrt_x {
            1e-7 * size.max(1.0)
        } else {
            1e-7 * speed.max(1.0)
        };
        for c in 0..nd {
            let mut fp = [0.0; MAX_LOAD_DOFS];
            for sgn in [1.0, -1.0] {
                let mut xp = *xl;
                let mut vp = *vl;
                if wrt_x {
                    xp[c / 3][c % 3] += sgn * h;
                } else {
                    vp[c / 3][c % 3] += sgn * h;
                }
                tmp.reset(nn);
                prov.element_load(e, t, &xp[..nn], &vp[..nn], Want::default(), tmp)
                    .map_err(err)?;
                for r in 0..nd {
                    fp[r] += sgn * tmp.force[r / 3][r % 3];
                }
            }
            for r in 0..nd {
                jac[r * nd + c] -= w * fp[r] / (2.0 * h);
            }
        }
        Ok(())
    };
    if want.dfdx && coef.k != 0.0 {
        if out.has_dfdx {
            for r in 0..nd {
                for c in 0..nd {
                    jac[r * nd + c] -= scale * coef.k * out.dfdx[r][c];
                }
            }
        } else if fd_dfdx {
            fd(true, scale * coef.k, jac)?;
        }
    }
    if want.dfdv && coef.c != 0.0 {
        if out.has_dfdv {
            for r in 0..nd {
                for c in 0..nd {
                    jac[r * nd + c] -= scale * coef.c * out.dfdv[r][c];
                }
            }
        } else {
            fd(false, scale * coef.c, jac)?;
        }
    }
    if jac.iter().any(|v| !v.is_finite()) {
        return Err(FemError::Load {
            element: e,
            message: "non-finite load derivative".into(),
        });
    }
    Ok(())
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
