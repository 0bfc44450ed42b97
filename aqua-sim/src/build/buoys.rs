//! `[[buoy]]` bodies on the structure (crate::buoy, docs/theory/farm.md#buoys): every buoy
//! is a point body of the structure (its mass, weight and seabed contact) and, when it has
//! volume or drag, a point element of the water loads with its shape.

use super::mesh::{default_name, ref_hint, resolve_ref};
use crate::design::Floater;
use crate::error::{Result, SimError};
use crate::scene::Scene;
use aqua_fem::{ModelBuilder, PointBody};
use aqua_hydro::assembly::PointElement;
use aqua_mesh::{BUOY_GROUP, Mesh};

/// The buoys' water-load elements and, for the design checks, what should float.
pub(super) fn attach_buoys(
    scene: &Scene,
    mesh: &Mesh,
    b: &mut ModelBuilder,
) -> Result<(Vec<PointElement>, Vec<Floater>)> {
    let file = scene.path.display().to_string();
    let mut points = Vec::new();
    let mut floaters = Vec::new();
    for (i, spec) in scene.buoy.iter().enumerate() {
        let at = format!("{file}: line {}: [[buoy]] #{}", spec.line, i + 1);
        let v = &spec.value;
        let buoy = v
            .resolve()
            .map_err(|m| SimError::input(format!("{at}: {m}")))?;
        let name = default_name(&v.name, "buoy", i);
        let reference = match &v.node {
            Some(r) => r.clone(),
            None => format!("{name}/{BUOY_GROUP}"),
        };
        let nodes = resolve_ref(mesh, &reference).ok_or_else(|| {
            SimError::Input(crate::error::InputError {
                message: format!(
                    "{at}: node = \"{reference}\" names no node; {}",
                    ref_hint(mesh, &reference)
                ),
                file: Some(scene.path.clone()),
                key: Some(format!("buoy.{i}.node")),
                value: Some(reference.clone()),
            })
        })?;
        for &n in &nodes {
            b.add_point_body(PointBody {
                node: n,
                mass: buoy.mass,
                force: [0.0; 3],
                seabed_stiffness: buoy.seabed_stiffness,
            })
            .map_err(|e| SimError::at(at.clone(), e))?;
            if let Some(props) = buoy.props {
                points.push(PointElement { node: n, props });
            }
        }
        if buoy.size > 0.0 {
            floaters.push(Floater {
                label: format!("buoy '{name}'"),
                location: name,
                nodes,
                size: buoy.size,
                submerged: v.submerged,
            });
        }
    }
    Ok((points, floaters))
}

/// Line groups meant to float (docs/theory/farm.md#design-warnings): buoyant,
/// ρ_w·π·d_v²/4 > μ, built with every node within one d_v of the still-water level, and with
/// no node `held` (fixed in all three directions).
pub(super) fn floating_pipes(
    mesh: &Mesh,
    sections: &[Option<(aqua_fem::GroupId, aqua_mesh::Section)>],
    water_density: f64,
    held: &dyn Fn(usize) -> bool,
) -> Vec<Floater> {
    let mut out = Vec::new();
    for (gi, g) in mesh.groups.iter().enumerate() {
        // A pipe held by a support (a fixed top ring and its links) is not meant to float.
        if g.nodes.iter().any(|&n| held(n)) {
            continue;
        }
        let Some((_, s)) = sections.get(gi).and_then(|s| s.as_ref()) else {
            continue;
        };
        let d = s.volume_diameter;
        let buoyant = water_density * std::f64::consts::PI * d * d / 4.0 > s.linear_mass();
        let at_surface = g.nodes.iter().all(|&n| mesh.nodes[n].z.abs() <= d);
        if d > 0.0 && buoyant && at_surface && !g.nodes.is_empty() {
            let name = format!("{}/{}", mesh.objects[g.object as usize].name, g.name);
            out.push(Floater {
                label: format!("floating pipe '{name}'"),
                location: name,
                nodes: g.nodes.clone(),
                size: d,
                submerged: false,
            });
        }
    }
    out
}
