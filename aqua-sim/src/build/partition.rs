//! The partition of the structure for the block solve of its linear systems
//! (docs/theory/fem.md#block-solve): every cage copy is a part of its own, everything else
//! (grid, lines, buoys, panels) one more part. aqua-fem eliminates each part's interior apart,
//! the cages in parallel, and then the DOFs where parts touch (a cage's bridle ends).

use aqua_mesh::{Mesh, ObjectKind};
use std::collections::BTreeMap;

/// The part of every mesh node, or `None` for fewer than two cage copies (nothing to split).
pub(super) fn cage_partition(mesh: &Mesh) -> Option<Vec<usize>> {
    let is_cage = |o: u32| {
        mesh.objects
            .get(o as usize)
            .is_some_and(|ob| matches!(ob.kind, ObjectKind::Cage(_)))
    };
    let mut part_of_cage: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for &owner in &mesh.node_owner {
        if is_cage(owner.0) {
            let next = part_of_cage.len() + 1;
            part_of_cage.entry(owner).or_insert(next);
        }
    }
    if part_of_cage.len() < 2 {
        return None;
    }
    Some(
        mesh.node_owner
            .iter()
            .map(|owner| part_of_cage.get(owner).copied().unwrap_or(0))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use aqua_mesh::{CageType, Object, ObjectDetail};

    fn object(kind: ObjectKind) -> Object {
        Object {
            name: String::new(),
            kind,
            origins: Vec::new(),
            net: None,
            detail: ObjectDetail::None,
        }
    }

    #[test]
    fn every_cage_copy_is_a_part_and_the_rest_one_more() {
        let mut mesh = Mesh {
            objects: vec![
                object(ObjectKind::Frame),
                object(ObjectKind::Cage(CageType::Cct)),
            ],
            node_owner: vec![(1, 0), (0, 0), (1, 1), (1, 0), (0, 0)],
            ..Mesh::default()
        };
        assert_eq!(cage_partition(&mesh), Some(vec![1, 0, 2, 1, 0]));
        mesh.node_owner = vec![(1, 0), (0, 0)];
        assert_eq!(cage_partition(&mesh), None, "one cage: nothing to split");
    }
}
