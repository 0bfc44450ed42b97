//! `[[body]]` free rigid bodies on the structure (crate::body, docs/theory/farm.md#rigid-bodies):
//! each is aqua-fem's rigid body holding the nodes of its object (hull layers and named
//! points), and each hull layer a prism of the water loads.

use crate::design::Floater;
use crate::error::{Result, SimError};
use crate::scene::Scene;
use aqua_fem::{ModelBuilder, PointBody, RigidBodySpec};
use aqua_hydro::assembly::PointElement;
use aqua_mesh::{HULL_GROUP, Mesh, ObjectKind};

/// The fraction of a body's mass its held points carry together (docs/theory/farm.md#rigid-bodies).
pub(crate) const HELD_POINT_MASS: f64 = 1e-6;

/// Adds every body; returns the hull prisms' water-load elements and, for the design checks,
/// each hull's top layer (sunk: its deck more than a layer under water) and bottom layer (on
/// the seabed).
pub(super) fn add_bodies(
    scene: &Scene,
    mesh: &Mesh,
    b: &mut ModelBuilder,
) -> Result<(Vec<PointElement>, Vec<Floater>)> {
    let file = scene.path.display().to_string();
    let mut points = Vec::new();
    let mut floaters = Vec::new();
    let bodies = mesh
        .objects
        .iter()
        .enumerate()
        .filter(|(_, o)| o.kind == ObjectKind::Body);
    for ((i, spec), (oi, obj)) in scene.body.iter().enumerate().zip(bodies) {
        let at = format!("{file}: line {}: [[body]] #{}", spec.line, i + 1);
        let body = spec
            .value
            .resolve()
            .map_err(|e| SimError::input(format!("{at}: {e}")))?;
        let held: Vec<usize> = mesh
            .groups
            .iter()
            .filter(|g| g.object as usize == oi)
            .flat_map(|g| g.nodes.iter().copied())
            .collect();
        // Every held point gets a nominal mass, HELD_POINT_MASS of the body's shared among
        // them, so the mass matrix stays regular where no member gives a point mass (a dry
        // hull layer, a fairlead before its line); the body keeps the total.
        let nominal = HELD_POINT_MASS * body.mass / held.len().max(1) as f64;
        for &node in &held {
            b.add_point_body(PointBody {
                node,
                mass: nominal,
                force: [0.0; 3],
                seabed_stiffness: 0.0,
            })
            .map_err(|e| SimError::at(at.clone(), e))?;
        }
        b.add_rigid_body(RigidBodySpec {
            name: obj.name.clone(),
            centre: body.centre,
            mass: body.mass * (1.0 - HELD_POINT_MASS),
            inertia: body.inertia,
            points: held,
        })
        .map_err(|e| SimError::at(at.clone(), e))?;
        let (Some(hull), Some(g)) = (
            body.hull,
            mesh.groups
                .iter()
                .find(|g| g.object as usize == oi && g.name == HULL_GROUP),
        ) else {
            continue;
        };
        points.extend(g.nodes.iter().map(|&node| PointElement {
            node,
            props: hull.column,
        }));
        let per_layer = hull.shape.columns[0] * hull.shape.columns[1];
        let n = g.nodes.len();
        let h = hull.shape.layer_height();
        floaters.push(Floater {
            label: format!("the hull of body '{}'", obj.name),
            location: format!("{}/{HULL_GROUP}", obj.name),
            nodes: g.nodes[n - per_layer..].to_vec(),
            size: h,
            submerged: false,
        });
        floaters.push(Floater {
            label: format!("the keel of body '{}'", obj.name),
            location: format!("{}/{HULL_GROUP}", obj.name),
            nodes: g.nodes[..per_layer].to_vec(),
            size: h,
            submerged: true,
        });
    }
    Ok((points, floaters))
}
