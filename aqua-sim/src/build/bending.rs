//! Bending hinges of the line groups whose section bends (docs/theory/fem.md#bending-of-sections):
//! one hinge at every node where exactly two elements of the group meet, and the joints of a
//! two-pipe collar's brackets with its pipes.

use crate::error::{Result, SimError};
use aqua_fem::{GroupId, ModelBuilder};
use aqua_mesh::{Mesh, Role, Section};
use std::collections::BTreeMap;

/// Adds the hinges of every bending group; returns how many were added.
pub(super) fn add_hinges(
    file: &str,
    mesh: &Mesh,
    sections: &[Option<(GroupId, Section)>],
    b: &mut ModelBuilder,
) -> Result<usize> {
    let mut count = 0;
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
        for [a, n, c] in chain_triples(mesh, &g.lines) {
            b.add_bending(a, n, c, ei).map_err(at)?;
            count += 1;
        }
        if g.role == Role::Brackets {
            for [a, n, c] in bracket_joints(mesh, g.object, &g.lines) {
                b.add_bending(a, n, c, ei).map_err(at)?;
                count += 1;
            }
        }
    }
    Ok(count)
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
