//! The points of a free rigid body (docs/theory/farm.md#rigid-bodies): the nodes the body holds
//! rigidly — the columns of its hull and its named points (fairleads) — as one object of kind
//! [`ObjectKind::Body`]. The body's mass, inertia and motion are the structure's
//! (aqua-fem's rigid body); this module only places the points.
//!
//! A box hull of length L (body x), width B (body y) and height H is represented by n_x × n_y
//! vertical columns, each of waterplane area A_c = L·B/(n_x·n_y), cut into n_z layers of height
//! H/n_z; each layer is a node (a prism of the water loads). The columns sit on a regular grid
//! stretched so the waterplane's second moments are the box's exactly:
//!
//! ```text
//! x_i = s_x·((i + ½)/n_x − ½)·L,   s_x = n_x/√(n_x² − 1)     (i = 0 … n_x − 1)
//! Σ A_c·x_i² = L·B·L²/12 = I_wp,y,   and the same in y
//! ```
//!
//! so volume, waterplane area and both waterplane moments (heave, roll and pitch stiffness) are
//! those of the box. The layers put the buoyancy at the height of the wet volume: every layer
//! under water pushes at its own centre, so only the layer the waterline cuts misplaces its part
//! by at most H/(2·n_z) (none when the waterline is a layer boundary).

use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Mesh, Object, ObjectDetail, ObjectKind, Role};
use nalgebra::Point3;

/// Node group of a body's hull columns.
pub const HULL_GROUP: &str = "hull";

/// A box hull, in the body frame (axes of the world as built, origin at the centre of gravity).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxHull {
    /// Length L along the body's x axis [m] (> 0).
    pub length: f64,
    /// Width B along the body's y axis [m] (> 0).
    pub width: f64,
    /// Height H, keel to deck [m] (> 0).
    pub height: f64,
    /// Centre of the box relative to the centre of gravity [m].
    pub centre: [f64; 3],
    /// Columns along x and y (each ≥ 2).
    pub columns: [usize; 2],
    /// Layers from keel to deck (≥ 1).
    pub layers: usize,
}

impl BoxHull {
    /// Checks the dimensions; `object` names the body in the error.
    pub fn validate(&self, object: &str) -> Result<()> {
        for (key, v) in [
            ("hull.length", self.length),
            ("hull.width", self.width),
            ("hull.height", self.height),
        ] {
            crate::limits::length(object, key, v, "")?;
        }
        if !self.centre.iter().all(|c| c.is_finite()) {
            return Err(MeshError::param(
                object,
                "hull.centre",
                format!("{:?}", self.centre),
                "three finite numbers [m]",
            ));
        }
        for (key, n) in [
            ("hull.columns[0]", self.columns[0]),
            ("hull.columns[1]", self.columns[1]),
        ] {
            if !(2..=50).contains(&n) {
                return Err(MeshError::param(
                    object,
                    key,
                    n,
                    "2 to 50 columns (two or more keep the roll and pitch stiffness)",
                ));
            }
        }
        if !(1..=50).contains(&self.layers) {
            return Err(MeshError::param(
                object,
                "hull.layers",
                self.layers,
                "1 to 50 layers",
            ));
        }
        Ok(())
    }

    /// Height of one layer, H/n_z [m].
    pub fn layer_height(&self) -> f64 {
        self.height / self.layers as f64
    }

    /// Waterplane area of one column, L·B/(n_x·n_y) [m²].
    pub fn column_area(&self) -> f64 {
        self.length * self.width / (self.columns[0] * self.columns[1]) as f64
    }

    /// Layer centres of every column in the body frame [m]: x fastest, then y, then z from the
    /// keel up.
    pub fn column_offsets(&self) -> Vec<[f64; 3]> {
        let along = |n: usize, len: f64| -> Vec<f64> {
            let nf = n as f64;
            let s = nf / (nf * nf - 1.0).sqrt();
            (0..n)
                .map(|i| s * ((i as f64 + 0.5) / nf - 0.5) * len)
                .collect()
        };
        let xs = along(self.columns[0], self.length);
        let ys = along(self.columns[1], self.width);
        let c = self.centre;
        let h = self.layer_height();
        let zs: Vec<f64> = (0..self.layers)
            .map(|k| c[2] - 0.5 * self.height + (k as f64 + 0.5) * h)
            .collect();
        let mut out = Vec::with_capacity(xs.len() * ys.len() * zs.len());
        for &z in &zs {
            for &y in &ys {
                for &x in &xs {
                    out.push([c[0] + x, c[1] + y, z]);
                }
            }
        }
        out
    }
}

/// The mesh of body `name` with its centre of gravity at `centre` [m] (world, as built): the
/// hull's columns (group [`HULL_GROUP`]) and one node group of one node per named point, at
/// `centre + offset`. Point names must be unique and not [`HULL_GROUP`].
pub fn body_mesh(
    name: &str,
    centre: [f64; 3],
    hull: Option<&BoxHull>,
    points: &[(String, [f64; 3])],
) -> Result<Mesh> {
    if !centre.iter().all(|c| c.is_finite()) {
        return Err(MeshError::param(
            name,
            "centre",
            format!("{centre:?}"),
            "three finite numbers [m]",
        ));
    }
    if hull.is_none() && points.is_empty() {
        return Err(MeshError::param(
            name,
            "hull",
            "none",
            "a body needs a [body.hull] or at least one [[body.point]] to hold",
        ));
    }
    let mut b = MeshBuilder::default();
    let at = |o: [f64; 3]| Point3::new(centre[0] + o[0], centre[1] + o[1], centre[2] + o[2]);
    if let Some(h) = hull {
        h.validate(name)?;
        let g = b.group(HULL_GROUP, Role::UserNodes, None);
        let nodes: Vec<usize> = h
            .column_offsets()
            .into_iter()
            .map(|o| b.add_node(at(o)))
            .collect();
        b.set_nodes(g, nodes);
    }
    for (k, (pname, o)) in points.iter().enumerate() {
        let key = format!("point[{k}]");
        if pname.is_empty() || pname == HULL_GROUP || pname.contains('/') {
            return Err(MeshError::param(
                name,
                &format!("{key}.name"),
                format!("\"{pname}\""),
                format!("a non-empty name without '/', other than \"{HULL_GROUP}\""),
            ));
        }
        if points[..k].iter().any(|(q, _)| q == pname) {
            return Err(MeshError::param(
                name,
                &format!("{key}.name"),
                format!("\"{pname}\""),
                "unique among the body's points",
            ));
        }
        if !o.iter().all(|c| c.is_finite()) {
            return Err(MeshError::param(
                name,
                &format!("{key}.position"),
                format!("{o:?}"),
                "three finite numbers [m], body frame",
            ));
        }
        let g = b.group(pname, Role::UserNodes, None);
        let n = b.add_node(at(*o));
        b.set_nodes(g, [n]);
    }
    b.mesh.objects.push(Object {
        name: name.to_string(),
        kind: ObjectKind::Body,
        origins: vec![centre],
        net: None,
        detail: ObjectDetail::None,
    });
    Ok(b.mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hull(nx: usize, ny: usize) -> BoxHull {
        BoxHull {
            length: 24.0,
            width: 12.0,
            height: 3.0,
            centre: [0.0, 0.0, -0.5],
            columns: [nx, ny],
            layers: 1,
        }
    }

    #[test]
    fn columns_keep_the_waterplane_moments_of_the_box() {
        for (nx, ny) in [(2, 2), (4, 2), (5, 3), (10, 7)] {
            let h = hull(nx, ny);
            let a = h.column_area();
            let cols = h.column_offsets();
            assert_eq!(cols.len(), nx * ny);
            let area: f64 = cols.iter().map(|_| a).sum();
            let sx: f64 = cols.iter().map(|c| a * c[0]).sum();
            let ixx: f64 = cols.iter().map(|c| a * c[1] * c[1]).sum();
            let iyy: f64 = cols.iter().map(|c| a * c[0] * c[0]).sum();
            assert!((area - 24.0 * 12.0).abs() < 1e-9);
            assert!(sx.abs() < 1e-9);
            // Box: I_x = L·B³/12, I_y = B·L³/12.
            assert!((ixx - 24.0 * 12f64.powi(3) / 12.0).abs() < 1e-6 * ixx);
            assert!((iyy - 12.0 * 24f64.powi(3) / 12.0).abs() < 1e-6 * iyy);
            assert!(cols.iter().all(|c| c[2] == -0.5));
        }
    }

    #[test]
    fn named_points_are_node_groups() {
        let pts = vec![
            ("f1".to_string(), [12.0, 6.0, 0.0]),
            ("f2".to_string(), [-12.0, -6.0, 0.0]),
        ];
        let mut h = hull(4, 2);
        h.layers = 3;
        let m = body_mesh("barge", [1.0, 2.0, 0.0], Some(&h), &pts).unwrap();
        assert_eq!(m.nodes.len(), 26);
        let zs: Vec<f64> = m.nodes[..24].iter().map(|p| p.z).collect();
        // Layer centres of a 3 m box centred 0.5 m under the centre of gravity at z = 0.
        assert_eq!(zs[0], -1.5);
        assert_eq!(zs[8], -0.5);
        assert_eq!(zs[16], 0.5);
        let f1 = m.groups.iter().find(|g| g.name == "f1").unwrap();
        assert_eq!(f1.nodes.len(), 1);
        assert_eq!(m.nodes[f1.nodes[0]], Point3::new(13.0, 8.0, 0.0));
        assert_eq!(m.objects[0].kind, ObjectKind::Body);
    }

    #[test]
    fn bad_points_and_hulls_name_the_key() {
        let dup = vec![
            ("f1".to_string(), [0.0; 3]),
            ("f1".to_string(), [1.0, 0.0, 0.0]),
        ];
        let e = body_mesh("b", [0.0; 3], None, &dup)
            .unwrap_err()
            .to_string();
        assert!(e.contains("point[1].name") && e.contains("unique"), "{e}");
        let e = body_mesh("b", [0.0; 3], Some(&hull(1, 2)), &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("hull.columns[0]"), "{e}");
        let e = body_mesh("b", [0.0; 3], None, &[]).unwrap_err().to_string();
        assert!(e.contains("hull"), "{e}");
    }
}
