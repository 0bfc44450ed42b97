//! DOF numbering and the sparse pattern of the free-DOF Jacobian, built once, with the
//! position of every element's and node's block in it.

use super::{NONE, System};
use crate::bending::HingeEval;
use crate::cable::CableEval;
use crate::error::{FemError, LoadError, Result};
use crate::loads::{LoadProvider, MAX_LOAD_NODES};
use crate::model::Model;
use crate::net_triangle::NetTriangleEval;
use crate::rigid_body::{BodyFrame, LinkEval};
use crate::rod::{ROD_DOFS, RodEval, RodVertex};

/// The five nodes of a rod vertex's stencil: three positions and two twist carriers.
fn rod_dof_nodes(v: &RodVertex) -> [usize; 5] {
    [
        v.nodes[0],
        v.nodes[1],
        v.nodes[2],
        v.carriers[0],
        v.carriers[1],
    ]
}

fn pos_in(col_ptr: &[usize], row_idx: &[usize], row: usize, col: usize) -> usize {
    let s = &row_idx[col_ptr[col]..col_ptr[col + 1]];
    col_ptr[col] + s.binary_search(&row).expect("entry in pattern")
}

/// The part of every node: its own from `given` (a prefix of the nodes), else that of its
/// lowest-numbered neighbour with one, spread until every node connected to a given one has
/// one; nodes left over go to part 0.
fn node_parts(given: &[usize], adj: &[Vec<usize>]) -> Vec<usize> {
    let mut part: Vec<usize> = (0..adj.len())
        .map(|i| given.get(i).copied().unwrap_or(NONE))
        .collect();
    loop {
        let mut changed = false;
        for i in 0..adj.len() {
            if part[i] == NONE
                && let Some(&j) = adj[i].iter().find(|&&j| part[j] != NONE)
            {
                part[i] = part[j];
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    for p in &mut part {
        if *p == NONE {
            *p = 0;
        }
    }
    part
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
                    error: LoadError::msg(format!(
                        "load element has {} nodes; 1 to {MAX_LOAD_NODES} are allowed",
                        nodes.len()
                    )),
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
                        error: LoadError::msg(format!("node {nd} listed twice")),
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
        for v in model.rod_vertices() {
            let dofs = rod_dof_nodes(v);
            for &p in &dofs {
                adj[p].extend(dofs.iter().filter(|&&q| q != p));
            }
        }
        for t in model.net_triangles() {
            for &p in &t.nodes {
                adj[p].extend(t.nodes.iter().filter(|&&q| q != p));
            }
        }
        for l in &model.links {
            let nodes = [l.node, l.centre, l.rotation];
            for &p in &nodes {
                adj[p].extend(nodes.iter().filter(|&&q| q != p));
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
        let part_of_free = model
            .partition()
            .map(|p| node_parts(p, &adj))
            .map(|np| dof_of_free.iter().map(|&d| np[d / 3]).collect());
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
        let mut net_pos = Vec::with_capacity(model.net_triangles().len());
        for t in model.net_triangles() {
            let mut p = [NONE; 81];
            for (i, &ni) in t.nodes.iter().enumerate() {
                for (j, &nj) in t.nodes.iter().enumerate() {
                    for ki in 0..3 {
                        for kj in 0..3 {
                            p[(3 * i + ki) * 9 + 3 * j + kj] = pos(ni, ki, nj, kj);
                        }
                    }
                }
            }
            net_pos.push(p);
        }
        let mut rod_pos = Vec::with_capacity(model.rod_vertices().len());
        for v in model.rod_vertices() {
            let mut p = [NONE; ROD_DOFS * ROD_DOFS];
            let at = |l: usize| {
                if l < 9 {
                    (v.nodes[l / 3], l % 3)
                } else {
                    (v.carriers[l - 9], 0)
                }
            };
            for i in 0..ROD_DOFS {
                for j in 0..ROD_DOFS {
                    let ((ni, ki), (nj, kj)) = (at(i), at(j));
                    p[i * ROD_DOFS + j] = pos(ni, ki, nj, kj);
                }
            }
            rod_pos.push(p);
        }
        let mut link_pos = Vec::with_capacity(model.links.len());
        for l in &model.links {
            let nodes = [l.node, l.centre, l.rotation];
            let mut p = [NONE; 81];
            for (i, &ni) in nodes.iter().enumerate() {
                for (j, &nj) in nodes.iter().enumerate() {
                    for ki in 0..3 {
                        for kj in 0..3 {
                            p[(3 * i + ki) * 9 + 3 * j + kj] = pos(ni, ki, nj, kj);
                        }
                    }
                }
            }
            link_pos.push(p);
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
            rod_pos,
            net_pos,
            node_pos,
            load_nodes,
            load_nn,
            load_pos_off,
            load_pos,
            load_stride,
            load_buf: vec![0.0; load_stride * nl],
            cable: vec![CableEval::default(); model.elements().len()],
            hinge: vec![HingeEval::default(); model.hinges().len()],
            rod: vec![RodEval::default(); model.rod_vertices().len()],
            net: vec![NetTriangleEval::default(); model.net_triangles().len()],
            rod_frames: model.rod_edges().iter().map(|e| e.frame).collect(),
            link_pos,
            link: vec![LinkEval::default(); model.links.len()],
            body_frames: vec![BodyFrame::default(); model.bodies.len()],
            gyro_c: vec![[[0.0; 3]; 3]; model.bodies.len()],
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
            part_of_free,
            schur: None,
            schur_active: false,
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
            n_stale_failures: 0,
            sym_skip: 0,
            sym_backoff: 0,
            n_refinement_sweeps: 0,
            load_scratch: Default::default(),
            secant: None,
            hht: None,
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
}
