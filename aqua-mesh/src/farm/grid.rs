//! The mooring grid of a farm: plate positions and cell centres ([`Grid`]), and the frame
//! object (plates, buoy nodes, frame lines, pendants, bridles to the collars).

use super::{FarmParams, segments};
use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Mesh, Object, ObjectKind, Role};
use crate::section::Section;
use nalgebra::{Point3, Vector3};

/// The grid's geometry.
pub(super) struct Grid {
    columns: usize,
    rows: usize,
    spacing: f64,
    depth: f64,
    origin: [f64; 2],
}

impl Grid {
    pub(super) fn new(p: &FarmParams) -> Self {
        Self {
            columns: p.columns as usize,
            rows: p.rows as usize,
            spacing: p.spacing,
            depth: p.grid_depth,
            origin: p.origin.unwrap_or([0.0, 0.0]),
        }
    }

    /// Plate index of intersection (i, j).
    pub(super) fn plate(&self, i: usize, j: usize) -> usize {
        j * (self.columns + 1) + i
    }

    pub(super) fn plate_position(&self, i: usize, j: usize) -> Point3<f64> {
        let x = self.origin[0] + (i as f64 - self.columns as f64 / 2.0) * self.spacing;
        let y = self.origin[1] + (j as f64 - self.rows as f64 / 2.0) * self.spacing;
        Point3::new(x, y, -self.depth)
    }

    /// Centre of slot (c, r), 1-based, at z = 0.
    pub(super) fn cell_centre(&self, c: usize, r: usize) -> Point3<f64> {
        let a = self.plate_position(c - 1, r - 1);
        Point3::new(a.x + self.spacing / 2.0, a.y + self.spacing / 2.0, 0.0)
    }

    /// Outer plates with their outward directions: (tag, i, j, direction).
    pub(super) fn outer_plates(&self) -> Vec<(char, usize, usize, Vector3<f64>)> {
        let (nc, nr) = (self.columns, self.rows);
        let mut v = Vec::new();
        for j in 0..=nr {
            v.push(('e', nc, j, Vector3::x()));
        }
        for i in 0..=nc {
            v.push(('n', i, nr, Vector3::y()));
        }
        for j in 0..=nr {
            v.push(('w', 0, j, -Vector3::x()));
        }
        for i in 0..=nc {
            v.push(('s', i, 0, -Vector3::y()));
        }
        v
    }
}

/// A straight line of elements of about `el` from node `from` to node `to` of group `g`.
pub(super) fn straight(b: &mut MeshBuilder, g: usize, from: usize, to: usize, el: f64) {
    let (a, end) = (b.mesh.nodes[from], b.mesh.nodes[to]);
    let n = segments((end - a).norm(), el);
    let mut prev = from;
    for k in 1..n {
        let node = b.add_node(a + (end - a) * (k as f64 / n as f64));
        b.add_line(g, prev, node, None);
        prev = node;
    }
    b.add_line(g, prev, to, None);
}

/// The collar node of `ring` that points most towards `dir` from `centre`; exact ties (a
/// corner between two nodes) go to the node farther from the centre line y = centre.y, then
/// x = centre.x, so that mirror-symmetric farms get mirror-symmetric bridles.
pub(super) fn collar_node(
    mesh: &Mesh,
    ring: &[usize],
    centre: Point3<f64>,
    dir: Vector3<f64>,
) -> Option<usize> {
    let key = |n: usize| {
        let d = mesh.nodes[n] - centre;
        (d.dot(&dir), d.y.abs(), d.x.abs())
    };
    let best = ring
        .iter()
        .map(|&n| key(n).0)
        .fold(f64::NEG_INFINITY, f64::max);
    let tol = 1e-9 * best.abs().max(1.0);
    ring.iter()
        .copied()
        .filter(|&n| key(n).0 >= best - tol)
        .max_by(|&a, &b| {
            let (ka, kb) = (key(a), key(b));
            ka.1.total_cmp(&kb.1).then(ka.2.total_cmp(&kb.2))
        })
}

/// The frame object: plates, buoy nodes, frame lines, pendants and bridles. The bridles'
/// collar ends are extra nodes at the end of the returned mesh; `welds` lists, in order, the
/// existing node of `mesh` each of them becomes (for [`Mesh::weld_tail`] after appending).
#[allow(clippy::type_complexity)]
pub(super) fn frame_object(
    name: &str,
    grid: &Grid,
    frame: &Section,
    bridle: &Section,
    el: f64,
    mesh: &Mesh,
    collars: &[((usize, usize), Point3<f64>, Vec<usize>)],
) -> Result<(Mesh, Vec<usize>, Vec<usize>)> {
    let mut b = MeshBuilder::default();
    let (nc, nr) = (grid.columns, grid.rows);
    for j in 0..=nr {
        for i in 0..=nc {
            b.add_node(grid.plate_position(i, j));
        }
    }
    let n_plates = (nc + 1) * (nr + 1);
    let buoys: Vec<usize> = (0..n_plates)
        .map(|p| {
            let q = b.mesh.nodes[p];
            b.add_node(Point3::new(q.x, q.y, 0.0))
        })
        .collect();
    let g_frame = b.group("frame_lines", Role::MooringLine, Some(frame.clone()));
    for j in 0..=nr {
        for i in 0..=nc {
            let p = grid.plate(i, j);
            if i < nc {
                let q = grid.plate(i + 1, j);
                straight(&mut b, g_frame, p, q, el);
            }
            if j < nr {
                let q = grid.plate(i, j + 1);
                straight(&mut b, g_frame, p, q, el);
            }
        }
    }
    let g_pend = b.group("pendants", Role::MooringLine, Some(frame.clone()));
    for (p, &top) in buoys.iter().enumerate() {
        straight(&mut b, g_pend, p, top, el);
    }
    let g_bridle = b.group("bridles", Role::MooringLine, Some(bridle.clone()));
    let mut welds = Vec::new();
    let mut ends = Vec::new();
    for ((c, r), centre, ring) in collars {
        for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
            let (i, j) = (c - 1 + di, r - 1 + dj);
            let plate = grid.plate_position(i, j);
            let dir = Vector3::new(plate.x - centre.x, plate.y - centre.y, 0.0);
            let target = collar_node(mesh, ring, *centre, dir).ok_or_else(|| {
                MeshError::inconsistent(name, "a farm cage has no top_ring to hang bridles on")
            })?;
            ends.push((grid.plate(i, j), target));
        }
    }
    // Bridle collar ends become the last nodes, in order.
    let mut pending = Vec::new();
    for (p, target) in ends {
        let a = b.mesh.nodes[p];
        let end = mesh.nodes[target];
        let n = segments((end - a).norm(), el);
        let mut prev = p;
        for k in 1..n {
            let node = b.add_node(a + (end - a) * (k as f64 / n as f64));
            b.add_line(g_bridle, prev, node, None);
            prev = node;
        }
        pending.push((prev, end, target));
    }
    for (prev, end, target) in pending {
        let node = b.add_node(end);
        b.add_line(g_bridle, prev, node, None);
        welds.push(target);
    }
    b.finish_element_nodes();
    let g = b.group("plates", Role::Plates, None);
    b.set_nodes(g, 0..n_plates);
    let g = b.group("buoys", Role::Buoys, None);
    b.set_nodes(g, buoys.iter().copied());
    b.mesh.objects.push(Object {
        name: name.to_string(),
        kind: ObjectKind::Frame,
        origins: vec![[grid.origin[0], grid.origin[1], -grid.depth]],
        net: None,
        detail: crate::model::ObjectDetail::None,
    });
    Ok((b.mesh, buoys, welds))
}
