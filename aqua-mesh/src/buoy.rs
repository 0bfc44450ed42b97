//! The node of a free buoy (`[[buoy]]` with a `position`, docs/theory/farm.md#buoys): one node
//! in an object of its own, node group `buoy`, so that lines can name it as their fairlead
//! (`"<name>/buoy"`). A buoy on an existing node needs no mesh of its own.

use crate::Mesh;
use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Object, ObjectKind, Role};
use nalgebra::Point3;

/// The node group of a buoy object.
pub const BUOY_GROUP: &str = "buoy";

/// A mesh of one node at `position` [m], object `name` of kind [`ObjectKind::Buoy`].
pub fn buoy_node(name: &str, position: [f64; 3]) -> Result<Mesh> {
    if !position.iter().all(|c| c.is_finite()) {
        return Err(MeshError::param(
            name,
            "position",
            format!("{position:?}"),
            "must be finite",
        ));
    }
    let mut b = MeshBuilder::default();
    let n = b.add_node(Point3::from(position));
    let g = b.group(BUOY_GROUP, Role::UserNodes, None);
    b.set_nodes(g, [n]);
    b.mesh.objects.push(Object {
        name: name.to_string(),
        kind: ObjectKind::Buoy,
        origins: vec![position],
        net: None,
        detail: crate::model::ObjectDetail::None,
    });
    Ok(b.mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_node_in_its_group() {
        let m = buoy_node("b1", [1.0, 2.0, -0.5]).unwrap();
        assert_eq!(m.nodes, vec![Point3::new(1.0, 2.0, -0.5)]);
        assert_eq!(m.resolve_nodes("b1/buoy"), Some(vec![0]));
        assert!(buoy_node("b1", [f64::NAN, 0.0, 0.0]).is_err());
    }
}
