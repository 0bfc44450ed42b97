//! Checks before a static solve: every connected part of the structure is held up, held
//! horizontally and not heavier than its full buoyancy (docs/theory/fem.md#static-solver).

use crate::error::{FemError, Result};
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::seabed::BedLaw;

/// The connected parts of the structure (joined by cable, net triangle, rod, rigid-link and
/// load elements):
/// the lowest node index of each node's part.
pub(super) fn parts<P: LoadProvider + ?Sized>(model: &Model, provider: &P) -> Vec<usize> {
    let n = model.n_nodes();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let union = |p: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(p, a), find(p, b));
        if ra != rb {
            p[ra.max(rb)] = ra.min(rb);
        }
    };
    for e in model.elements() {
        union(&mut parent, e.a, e.b);
    }
    for t in model.net_triangles() {
        union(&mut parent, t.nodes[0], t.nodes[1]);
        union(&mut parent, t.nodes[0], t.nodes[2]);
    }
    for e in model.rod_edges() {
        union(&mut parent, e.nodes[0], e.nodes[1]);
        union(&mut parent, e.nodes[0], e.carrier);
    }
    for l in &model.links {
        union(&mut parent, l.node, l.centre);
        union(&mut parent, l.node, l.rotation);
    }
    for b in model.rigid_bodies() {
        union(&mut parent, b.node, b.rotation_node);
    }
    for e in 0..provider.n_elements() {
        let nodes = provider.element_nodes(e);
        for w in nodes.windows(2) {
            if w[0] < n && w[1] < n {
                union(&mut parent, w[0], w[1]);
            }
        }
    }
    (0..n).map(|i| find(&mut parent, i)).collect()
}

/// Whether DOF k of node i holds its part: constrained, and not a rod's twist carrier (whose
/// held coordinates are placeholders, docs/theory/fem.md#rod) nor a rigid body's rotation
/// carrier (a held rotation holds no position, docs/theory/fem.md#rigid-bodies).
fn holds(model: &Model, i: usize, k: usize) -> bool {
    model.is_constrained(i, k) && !model.is_twist_carrier(i) && !model.is_rotation_carrier(i)
}

/// The structure's nodes of part `r` (twist carriers left out).
fn part_nodes(model: &Model, part: &[usize], r: usize) -> Vec<usize> {
    (0..part.len())
        .filter(|&j| part[j] == r && !model.is_auxiliary(j))
        .collect()
}

/// Connected parts held by nothing.
pub(super) fn check_supported<P: LoadProvider + ?Sized>(
    model: &Model,
    provider: &P,
    part: &[usize],
) -> Result<()> {
    let n = model.n_nodes();
    let mut held = vec![false; n];
    provider.mark_restoring_nodes(&mut held);
    let bed = BedLaw::new(model, false);
    let mut comp_held = vec![false; n];
    let mut comp_size = vec![0usize; n];
    for i in 0..n {
        let r = part[i];
        comp_size[r] += usize::from(!model.is_auxiliary(i));
        let c = (0..3).any(|k| holds(model, i, k)) || held[i] || bed.acts_on(model, i);
        comp_held[r] |= c;
    }
    for i in 0..n {
        if part[i] == i && !comp_held[i] {
            return Err(FemError::Unconstrained {
                first_node: i,
                n_nodes: comp_size[i],
                nodes: part_nodes(model, part, i),
            });
        }
    }
    Ok(())
}

/// Parts with no node fixed in x (or y) whose external loads `fext` (evaluated at the
/// as-built position) have a resultant along that axis: nothing can balance it in statics,
/// where only fixed DOFs act horizontally (seabed contact and buoyancy are vertical, no
/// seabed friction; docs/theory/fem.md#static-solver). Each axis is judged alone: a part
/// fixed in y only and pushed along x drifts along x. A resultant below 1e-6 of the part's
/// Σ|f| is round-off.
pub(super) fn check_held_horizontally(
    model: &Model,
    part: &[usize],
    fext: &[[f64; 3]],
) -> Result<()> {
    let n = model.n_nodes();
    // Per part: fixed in x, fixed in y, resultant, Σ|f|.
    let mut fixed = vec![[false; 2]; n];
    let mut sum = vec![[0.0f64; 2]; n];
    let mut abs = vec![0.0f64; n];
    for i in 0..n {
        let r = part[i];
        for k in 0..2 {
            fixed[r][k] |= holds(model, i, k);
            sum[r][k] += fext[i][k];
        }
        abs[r] += fext[i].iter().map(|f| f.abs()).sum::<f64>();
    }
    for r in 0..n {
        if part[r] != r {
            continue;
        }
        let pushed = |k: usize| !fixed[r][k] && sum[r][k].abs() > 1e-6 * abs[r] + 1e-9;
        let dirs: Vec<&str> = [(0, "x"), (1, "y")]
            .into_iter()
            .filter(|&(k, _)| pushed(k))
            .map(|(_, d)| d)
            .collect();
        if !dirs.is_empty() {
            let nodes = part_nodes(model, part, r);
            return Err(FemError::Drifting {
                first_node: r,
                n_nodes: nodes.len(),
                free_dirs: dirs.join(" and "),
                force: sum[r],
                nodes,
            });
        }
    }
    Ok(())
}

/// Parts with no node fixed in z and no seabed contact whose weights and point forces pull
/// them down harder than their buoyancy can hold them, fully submerged
/// ([`FemError::Sinking`]): without it such a part sinks for hundreds of iterations
/// (docs/theory/fem.md#static-solver). Skipped if the provider cannot give its largest
/// buoyancy.
pub(super) fn check_held_up<P: LoadProvider + ?Sized>(
    model: &Model,
    provider: &P,
    part: &[usize],
) -> Result<()> {
    let n = model.n_nodes();
    let mut lift = vec![0.0; n];
    if !provider.max_buoyancy(&mut lift) {
        return Ok(());
    }
    let bed = BedLaw::new(model, false);
    let mut held = vec![false; n];
    let (mut down, mut up) = (vec![0.0f64; n], vec![0.0f64; n]);
    for i in 0..n {
        let r = part[i];
        held[r] |= holds(model, i, 2) || bed.acts_on(model, i);
        down[r] -= model.weight[i][2] + model.point_force[i][2];
        up[r] += lift[i];
    }
    for r in 0..n {
        if part[r] == r && !held[r] && down[r] > up[r] * (1.0 + 1e-9) + 1e-9 {
            let nodes = part_nodes(model, part, r);
            return Err(FemError::Sinking {
                first_node: r,
                n_nodes: nodes.len(),
                weight: down[r],
                buoyancy: up[r],
                nodes,
            });
        }
    }
    Ok(())
}
