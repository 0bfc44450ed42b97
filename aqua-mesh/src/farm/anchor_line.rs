//! The anchor lines of a farm: chain and rope from a fixed anchor on the seabed to a plate,
//! hanging as a catenary.

use super::segments;
use crate::error::{MeshError, Result};
use crate::line::hanging_points;
use crate::mesh_builder::MeshBuilder;
use crate::model::{Mesh, Object, ObjectKind, Role};
use crate::section::Section;
use nalgebra::Point3;

/// An anchor line from `anchor` (fixed, on the seabed `zb`) to `fairlead`: consecutive parts
/// (group name, section, unstretched length) from the anchor, each with elements of about
/// `el`; initial shape the inextensible catenary of the total length stretched by the strain
/// `stretch`, with touchdown when it lies on the seabed (as a `[[line]]`'s). Groups as a
/// `[[line]]` (`anchor`, `fairlead`, `line_nodes`, `fixed` = anchor).
pub fn anchor_line(
    name: &str,
    anchor: Point3<f64>,
    fairlead: Point3<f64>,
    parts: &[(&str, Section, f64)],
    el: f64,
    zb: f64,
    stretch: f64,
) -> Result<Mesh> {
    let total: f64 = parts.iter().map(|p| p.2).sum();
    let counts: Vec<usize> = parts.iter().map(|p| segments(p.2, el)).collect();
    let n: usize = counts.iter().sum();
    let arc: Vec<f64> = (0..=n).map(|i| total * i as f64 / n as f64).collect();
    let mut pts = hanging_points(anchor, fairlead, total, &arc, Some(zb), stretch);
    if pts.is_empty() {
        return Err(MeshError::inconsistent(
            name,
            "anchor and fairlead coincide",
        ));
    }
    for p in pts.iter_mut() {
        p.z = p.z.max(zb);
    }
    let mut b = MeshBuilder::default();
    let mut notices = Vec::new();
    let chord = (fairlead - anchor).norm();
    if total < chord && (chord - total) / total > 0.01 {
        notices.push(format!(
            "warning: {name}: length {total} m is shorter than the chord {chord:.4} m; the line \
             starts stretched by {:.2} %",
            100.0 * (chord - total) / total
        ));
    }
    for p in pts {
        b.add_node(p);
    }
    let mut k0 = 0;
    for ((g, section, len), &m) in parts.iter().zip(&counts) {
        let gi = b.group(g, Role::MooringLine, Some(section.clone()));
        for k in k0..k0 + m {
            b.add_line(gi, k, k + 1, Some(len / m as f64));
        }
        k0 += m;
    }
    b.finish_element_nodes();
    for (g, role, nodes) in [
        ("anchor", Role::Anchor, vec![0]),
        ("fairlead", Role::Fairlead, vec![n]),
        ("line_nodes", Role::LineNodes, (0..=n).collect()),
        ("fixed", Role::Fixed, vec![0]),
    ] {
        let gi = b.group(g, role, None);
        b.set_nodes(gi, nodes);
    }
    b.mesh.objects.push(Object {
        name: name.to_string(),
        kind: ObjectKind::Line,
        origins: vec![[anchor.x, anchor.y, anchor.z]],
        net: None,
        detail: crate::model::ObjectDetail::None,
    });
    b.mesh.notices = notices;
    Ok(b.mesh)
}
