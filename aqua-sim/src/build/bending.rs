//! Bending of the line groups whose section bends (docs/theory/fem.md#bending-of-sections):
//! along every chain of a group's elements (nodes where exactly two of them meet), a rod
//! (bending about both axes and torsion, docs/theory/fem.md#rod; the default) or a hinge at each
//! interior node (`bending_element = "hinge"`); and the joints of a two-pipe collar's brackets
//! with its pipes (hinges). A clamped node (`[[fix]] clamp = true`) ends the chains through it.

use crate::error::{Result, SimError};
use aqua_fem::{GroupId, ModelBuilder, RodSection};
use aqua_mesh::{BendingElement, Mesh, Role, Section};
use std::collections::{BTreeMap, BTreeSet};

/// Adds the rods or hinges of every bending group; returns how many rods and hinges were
/// added. `clamped` are the nodes whose rotation is held.
pub(super) fn add_bending(
    file: &str,
    mesh: &Mesh,
    sections: &[Option<(GroupId, Section)>],
    clamped: &BTreeSet<usize>,
    b: &mut ModelBuilder,
) -> Result<(usize, usize)> {
    let (mut rods, mut count) = (0, 0);
    let mut clamp_used = BTreeSet::new();
    for (gi, g) in mesh.groups.iter().enumerate() {
        let Some((_, section)) = &sections[gi] else {
            continue;
        };
        let ei = section.bending_stiffness();
        if ei <= 0.0 {
            continue;
        }
        let name = format!("{}/{}", mesh.objects[g.object as usize].name, g.name);
        let at = |e| SimError::at(format!("{file}: bending of group {name}"), e);
        match section.bending_element {
            BendingElement::Rod => {
                let rod = RodSection {
                    ei,
                    gj: section.torsional_stiffness(),
                    spin_inertia: section.spin_inertia(),
                };
                for (nodes, closed) in chains(mesh, &g.lines, clamped) {
                    let ends = if closed {
                        [false, false]
                    } else {
                        [nodes[0], nodes[nodes.len() - 1]].map(|n| clamped.contains(&n))
                    };
                    if nodes.len() < 3 && !ends.iter().any(|&c| c) {
                        continue;
                    }
                    for (&n, &c) in [nodes[0], nodes[nodes.len() - 1]].iter().zip(&ends) {
                        if c {
                            clamp_used.insert(n);
                        }
                    }
                    b.add_rod(&nodes, rod, closed, ends).map_err(at)?;
                    rods += 1;
                }
            }
            BendingElement::Hinge => {
                for [a, n, c] in chain_triples(mesh, &g.lines) {
                    b.add_bending(a, n, c, ei).map_err(at)?;
                    count += 1;
                }
            }
        }
        if g.role == Role::Brackets {
            for [a, n, c] in bracket_joints(mesh, g.object, &g.lines) {
                b.add_bending(a, n, c, ei).map_err(at)?;
                count += 1;
            }
        }
    }
    if let Some(n) = clamped.difference(&clamp_used).next() {
        return Err(SimError::input(format!(
            "{file}: [[fix]] clamp = true at node {n}, which is on no pipe modelled as a rod: a \
             clamp holds a rod's rotation (a group with bending and bending_element = \"rod\"); \
             use `dofs` alone to hold a position"
        )));
    }
    Ok((rods, count))
}

/// The chains of a group's elements: maximal node paths through nodes where exactly two of
/// its elements meet, split at clamped nodes; `true` for a closed ring (no branch or clamp on
/// it). Chains of one element are kept (a clamped end bends there).
fn chains(mesh: &Mesh, lines: &[usize], clamped: &BTreeSet<usize>) -> Vec<(Vec<usize>, bool)> {
    let nb = neighbours(mesh, lines);
    let through = |n: usize| {
        nb.get(&n)
            .is_some_and(|o| o.len() == 2 && o[0] != o[1] && !clamped.contains(&n))
    };
    let mut used: BTreeSet<(usize, usize)> = BTreeSet::new();
    let mut out = Vec::new();
    let edge = |a: usize, b: usize| (a.min(b), a.max(b));
    let walk = |start: usize, next: usize, used: &mut BTreeSet<(usize, usize)>| {
        let mut path = vec![start, next];
        used.insert(edge(start, next));
        let (mut prev, mut cur) = (start, next);
        while through(cur) && cur != start {
            let o = &nb[&cur];
            let nxt = if o[0] == prev { o[1] } else { o[0] };
            if used.contains(&edge(cur, nxt)) {
                break;
            }
            used.insert(edge(cur, nxt));
            path.push(nxt);
            prev = cur;
            cur = nxt;
        }
        path
    };
    // Open chains from every end (a node that is not passed through).
    for (&n, o) in &nb {
        if through(n) {
            continue;
        }
        for &m in o {
            if m != n && !used.contains(&edge(n, m)) {
                let path = walk(n, m, &mut used);
                out.push((path, false));
            }
        }
    }
    // What is left are rings.
    for (&n, o) in &nb {
        if o.len() == 2 && o[0] != o[1] && !used.contains(&edge(n, o[0])) {
            let mut path = walk(n, o[0], &mut used);
            if path.len() > 3 && path.last() == Some(&n) {
                path.pop();
                out.push((path, true));
            }
        }
    }
    out
}

/// The other ends of the given elements at each node, nodes in increasing order.
fn neighbours(mesh: &Mesh, lines: &[usize]) -> BTreeMap<usize, Vec<usize>> {
    let mut map: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &e in lines {
        let [p, q] = mesh.lines[e].nodes;
        map.entry(p).or_default().push(q);
        map.entry(q).or_default().push(p);
    }
    map
}

/// Hinges (a, n, c) of a group: at each node n where exactly two of its elements meet (n–a and
/// n–c, a ≠ c). Open chains get hinges at their interior nodes, closed rings at every node;
/// chain ends (one element) and branch nodes (three or more) get none, so no hinge joins two
/// elements that merely share a node with others.
fn chain_triples(mesh: &Mesh, lines: &[usize]) -> Vec<[usize; 3]> {
    neighbours(mesh, lines)
        .into_iter()
        .filter(|(_, o)| o.len() == 2 && o[0] != o[1])
        .map(|(n, o)| [o[0], n, o[1]])
        .collect()
}

/// Hinges (m, n, o) that hold each bracket n–o at its as-built angle to the collar pipe
/// elements n–m (groups `top_ring` and `outer_ring` of the same object) at both of its ends.
fn bracket_joints(mesh: &Mesh, object: u32, brackets: &[usize]) -> Vec<[usize; 3]> {
    let ring_lines: Vec<usize> = mesh
        .groups
        .iter()
        .filter(|g| g.object == object && matches!(g.role, Role::TopRing | Role::OuterRing))
        .flat_map(|g| g.lines.iter().copied())
        .collect();
    let ring = neighbours(mesh, &ring_lines);
    let mut out = Vec::new();
    for &e in brackets {
        let [p, q] = mesh.lines[e].nodes;
        for (n, o) in [(p, q), (q, p)] {
            for &m in ring.get(&n).map(Vec::as_slice).unwrap_or(&[]) {
                if m != o {
                    out.push([m, n, o]);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use aqua_mesh::{LineElement, Mesh};
    use nalgebra::Point3;

    fn mesh(n_nodes: usize, lines: &[[usize; 2]]) -> Mesh {
        Mesh {
            nodes: (0..n_nodes)
                .map(|i| Point3::new(i as f64, 0.0, 0.0))
                .collect(),
            lines: lines
                .iter()
                .map(|&nodes| LineElement {
                    nodes,
                    group: 0,
                    object: 0,
                    copy: 0,
                    rest_length: None,
                    section_scale: 1.0,
                })
                .collect(),
            ..Default::default()
        }
    }

    #[test]
    fn rod_chains_follow_rings_branches_and_clamps() {
        let none = BTreeSet::new();
        // Ring 0-1-2-3-0: one closed chain of four nodes.
        let m = mesh(4, &[[0, 1], [1, 2], [2, 3], [3, 0]]);
        let c = chains(&m, &[0, 1, 2, 3], &none);
        assert_eq!(c.len(), 1);
        assert!(c[0].1 && c[0].0.len() == 4, "{c:?}");
        // The same ring clamped at node 2: one open chain from 2 round to 2.
        let c = chains(&m, &[0, 1, 2, 3], &BTreeSet::from([2]));
        assert_eq!(c, vec![(vec![2, 1, 0, 3, 2], false)]);
        // A star of three arms from node 0 (0-1-4, 0-2, 0-3): three open chains.
        let m = mesh(5, &[[0, 1], [0, 2], [0, 3], [1, 4]]);
        let c = chains(&m, &[0, 1, 2, 3], &none);
        assert_eq!(c.len(), 3, "{c:?}");
        assert!(c.iter().any(|(p, _)| p == &vec![0, 1, 4]));
        // An open chain clamped inside: two chains meeting at the clamp.
        let m = mesh(5, &[[0, 1], [1, 2], [2, 3], [3, 4]]);
        let c = chains(&m, &[0, 1, 2, 3], &BTreeSet::from([2]));
        assert_eq!(c, vec![(vec![0, 1, 2], false), (vec![2, 3, 4], false)]);
    }

    #[test]
    fn chains_rings_and_branches() {
        // Open chain 0-1-2-3: hinges at 1 and 2.
        let m = mesh(4, &[[0, 1], [1, 2], [2, 3]]);
        assert_eq!(chain_triples(&m, &[0, 1, 2]), vec![[0, 1, 2], [1, 2, 3]]);
        // Ring 0-1-2-3-0: a hinge at every node.
        let m = mesh(4, &[[0, 1], [1, 2], [2, 3], [3, 0]]);
        assert_eq!(chain_triples(&m, &[0, 1, 2, 3]).len(), 4);
        // A star of three arms from node 0 (0-1-4, 0-2, 0-3): no hinge at the branch node 0,
        // one at node 1 inside the first arm.
        let m = mesh(5, &[[0, 1], [0, 2], [0, 3], [1, 4]]);
        assert_eq!(chain_triples(&m, &[0, 1, 2, 3]), vec![[0, 1, 4]]);
        // Two elements on the same pair of nodes: no hinge.
        let m = mesh(2, &[[0, 1], [1, 0]]);
        assert!(chain_triples(&m, &[0, 1]).is_empty());
    }
}
