//! The structural model (aqua-fem) of a scene: one cable group per mesh line group
//! ("object/group") with `[[group]]` overrides applied, the cables, point masses from the
//! builders' weights, `[[point]]` and `[[buoy]]`, fixed nodes from the builders' `fixed` groups and
//! `[[fix]]`, and the `[[prescribed]]` motions (or externally driven ones for a coupling).

use super::mesh::{ref_hint, resolve_ref};
use crate::error::{Result, SimError};
use crate::scene::{GroupSpec, Located, MotionKind, PrescribedSpec, Scene};
use aqua_env::{Constants, Depth};
use aqua_fem::{
    AxialDamping, CableSection, Dofs, Environment, ExternalMotion, GroupId, ModelBuilder, Motion,
    NetGroupId, NetTriangleSection, PointBody, UnstretchedLength,
};
use aqua_hydro::assembly::PointElement;
use aqua_hydro::{PointProps, PointShape};
use aqua_mesh::{Mesh, PanelNodes, Section};
use std::collections::{BTreeSet, HashMap};

/// How prescribed nodes move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Prescribed {
    /// As the scene's `[[prescribed]]` motions say.
    #[default]
    AsScene,
    /// Driven from outside, step by step (a coupling): every `[[prescribed]]` node gets an
    /// [`ExternalMotion`] that starts at rest at its as-built position.
    External,
}

/// What [`build_structure`] returns besides the model builder.
#[derive(Debug)]
pub(super) struct Structure {
    /// The builder, complete but for [`ModelBuilder::build`].
    pub builder: ModelBuilder,
    /// Per mesh group: the fem group id and the section with overrides applied.
    pub sections: Vec<Option<(GroupId, Section)>>,
    /// Names of the structural groups: the cable groups (index = fem group id), then the net
    /// triangle groups.
    pub group_names: Vec<String>,
    /// Point bodies that carry water loads (volume or drag).
    pub hydro_points: Vec<PointElement>,
    /// Nodes with fixed or prescribed DOFs.
    pub supported: BTreeSet<usize>,
    /// Externally driven nodes: `[[prescribed]]` reference, its nodes and their motions.
    pub external: Vec<(String, Vec<(usize, ExternalMotion)>)>,
    /// The `[[buoy]]`s that should float (for the design checks).
    pub buoys: Vec<crate::design::Floater>,
    /// Per mesh panel: its net triangle in the model, if it is one.
    pub panel_triangle: Vec<Option<usize>>,
}

/// The structural environment: gravity, water density and the seabed
/// (docs/theory/environment.md#fluid-constants).
pub(super) fn environment(scene: &Scene, constants: &Constants) -> Environment {
    Environment {
        gravity: constants.gravity,
        water_density: constants.density,
        seabed: match constants.depth {
            Depth::Finite(h) => Some(scene.seabed.seabed(h)),
            Depth::Infinite => None,
        },
    }
}

/// Builds the structural model of the mesh.
pub(super) fn build_structure(
    scene: &Scene,
    mesh: &Mesh,
    env: Environment,
    prescribed: Prescribed,
) -> Result<Structure> {
    let file = scene.path.display().to_string();
    let gravity = env.gravity;
    let mut b = ModelBuilder::new(env);
    for p in &mesh.nodes {
        b.add_node([p.x, p.y, p.z])
            .map_err(|e| SimError::at(format!("{file}: node"), e))?;
    }
    let (sections, mut group_names) = cable_groups(scene, mesh, &mut b)?;
    add_cables(&file, mesh, &sections, &mut b)?;
    let panel_triangle = add_net_triangles(&file, mesh, &mut b, &mut group_names)?;
    // Sinkers and weights of the builders hang as point masses W/g
    // (docs/theory/cages.md#frame-ropes-and-weights).
    for w in &mesh.weights {
        b.add_point_body(PointBody {
            node: w.node,
            mass: w.weight / gravity,
            force: [0.0; 3],
            seabed_stiffness: 0.0,
        })
        .map_err(|e| SimError::at(format!("{file}: sinker weight"), e))?;
    }
    let mut hydro_points = point_bodies(scene, mesh, &mut b)?;
    let (buoy_points, buoys) = super::buoys::attach_buoys(scene, mesh, &mut b)?;
    hydro_points.extend(buoy_points);
    let (mut supported, clamped) = fixed_nodes(scene, mesh, &mut b)?;
    let external = prescribed_motions(scene, mesh, prescribed, &mut b, &mut supported)?;
    // Last: a rod adds its twist carriers (and ghost nodes at clamps) after every node above,
    // a rigid body its centre and rotation nodes.
    super::bending::add_bending(&file, mesh, &sections, &clamped, &mut b)?;
    let (body_points, body_floaters) = super::bodies::add_bodies(scene, mesh, &mut b)?;
    hydro_points.extend(body_points);
    let mut buoys = buoys;
    buoys.extend(body_floaters);
    Ok(Structure {
        builder: b,
        sections,
        group_names,
        hydro_points,
        supported,
        external,
        buoys,
        panel_triangle,
    })
}

/// The net triangles of every net with `net.element = "triangle"`, one group per object
/// ("object/net_triangles") with the section of one physical twine: EA = E·πd²/4,
/// μ = ρ·πd²/4, bar length l_p, tension-only (docs/theory/fem.md#net-triangle), its name
/// appended to `group_names` (after the cable groups). Returns per mesh panel its triangle
/// index.
fn add_net_triangles(
    file: &str,
    mesh: &Mesh,
    b: &mut ModelBuilder,
    group_names: &mut Vec<String>,
) -> Result<Vec<Option<usize>>> {
    let mut group: HashMap<u32, NetGroupId> = HashMap::new();
    let mut out = vec![None; mesh.panels.len()];
    for (pi, p) in mesh.panels.iter().enumerate() {
        let (Some(uv), PanelNodes::Tri(nodes)) = (p.uv, p.nodes) else {
            continue;
        };
        let obj = &mesh.objects[p.object as usize];
        let Some(net) = &obj.net else { continue };
        let id = match group.get(&p.object) {
            Some(&id) => id,
            None => {
                let area = std::f64::consts::FRAC_PI_4 * net.twine_diameter.powi(2);
                let section = NetTriangleSection::new(
                    net.youngs_modulus * area,
                    net.half_mesh,
                    net.density * area,
                )
                .with_compression_ratio(aqua_mesh::section::TENSION_ONLY);
                let name = format!("{}/net_triangles", obj.name);
                let id = b
                    .add_net_triangle_group(&name, section)
                    .map_err(|e| SimError::at(format!("{file}: {name}"), e))?;
                group.insert(p.object, id);
                group_names.push(name);
                id
            }
        };
        out[pi] = Some(
            b.add_net_triangle(id, nodes, uv)
                .map_err(|e| SimError::at(format!("{file}: {}: net triangle", obj.name), e))?,
        );
    }
    Ok(out)
}

/// The `[[group]]` entry for a mesh group: "object/group" first, then "group".
pub(super) fn group_spec<'a>(
    scene: &'a Scene,
    object: &str,
    group: &str,
) -> Option<(usize, &'a Located<GroupSpec>)> {
    let full = format!("{object}/{group}");
    let find = |name: &str| scene.group.iter().position(|g| g.value.name == name);
    find(&full)
        .or_else(|| find(group))
        .map(|k| (k, &scene.group[k]))
}

/// One cable group per mesh line group, its section with the `[[group]]` overrides applied
/// (docs/theory/fem.md#sections). Every `[[group]]` must match a group.
#[allow(clippy::type_complexity)]
fn cable_groups(
    scene: &Scene,
    mesh: &Mesh,
    b: &mut ModelBuilder,
) -> Result<(Vec<Option<(GroupId, Section)>>, Vec<String>)> {
    let file = scene.path.display().to_string();
    let mut fem_group = vec![None; mesh.groups.len()];
    let mut group_names = Vec::new();
    let mut used = vec![false; scene.group.len()];
    for (gi, g) in mesh.groups.iter().enumerate() {
        if g.lines.is_empty() {
            continue;
        }
        let object = &mesh.objects[g.object as usize].name;
        let mut section = mesh.groups[gi].section.clone().ok_or_else(|| {
            SimError::input(format!(
                "{file}: group {object}/{} has lines but no section",
                g.name
            ))
        })?;
        if let Some((k, spec)) = group_spec(scene, object, &g.name) {
            used[k] = true;
            spec.value
                .section
                .apply(object, &format!("group.{}", g.name), &mut section)
                .map_err(|e| {
                    SimError::at(
                        format!("{file}: line {}: [[group]] {}", spec.line, spec.value.name),
                        e,
                    )
                })?;
        }
        let name = format!("{object}/{}", g.name);
        let id = b
            .add_group(&name, cable_section(&section))
            .map_err(|e| SimError::at(format!("{file}: {name}"), e))?;
        fem_group[gi] = Some((id, section));
        group_names.push(name);
    }
    if let Some(k) = used.iter().position(|u| !u) {
        let g = &scene.group[k];
        let valid: BTreeSet<&str> = mesh
            .groups
            .iter()
            .filter(|g| !g.lines.is_empty())
            .map(|g| g.name.as_str())
            .collect();
        return Err(SimError::input(format!(
            "{file}: line {}: [[group]] name = \"{}\" matches no element group; valid: {}",
            g.line,
            g.value.name,
            valid.into_iter().collect::<Vec<_>>().join(", ")
        )));
    }
    Ok((fem_group, group_names))
}

/// The cable section of a mesh section: EA, μ, compression ratio, axial damping and seabed
/// contact (docs/theory/fem.md#sections).
fn cable_section(section: &Section) -> CableSection {
    let mut cs = CableSection::new(section.axial_stiffness(), section.linear_mass())
        .with_compression_ratio(section.compression_ratio);
    if let Some(c) = section.axial_damping {
        cs = cs.with_axial_damping(AxialDamping::Coefficient(c));
    } else if let Some(r) = section.axial_damping_ratio {
        cs = cs.with_axial_damping(AxialDamping::Ratio(r));
    }
    if section.seabed {
        cs = cs.with_contact(section.contact_diameter.unwrap_or(section.volume_diameter));
    }
    cs
}

/// One cable per mesh line, unstretched length given or as built with the section's initial
/// tension.
fn add_cables(
    file: &str,
    mesh: &Mesh,
    sections: &[Option<(GroupId, Section)>],
    b: &mut ModelBuilder,
) -> Result<()> {
    for (e, l) in mesh.lines.iter().enumerate() {
        let (gid, section) = sections[l.group].as_ref().ok_or_else(|| {
            SimError::input(format!(
                "{file}: element {e} belongs to a group without a section"
            ))
        })?;
        let len = match l.rest_length {
            Some(l0) => UnstretchedLength::Given(l0),
            None => UnstretchedLength::AsBuilt {
                initial_tension: section.initial_tension,
            },
        };
        b.add_scaled_cable(l.nodes[0], l.nodes[1], *gid, len, l.section_scale)
            .map_err(|err| SimError::at(format!("{file}: element {e}"), err))?;
    }
    Ok(())
}

/// The nodes of a node group reference of the scene entry `at`.
fn node_group(mesh: &Mesh, at: &str, reference: &str) -> Result<Vec<usize>> {
    resolve_ref(mesh, reference).ok_or_else(|| {
        SimError::input(format!(
            "{at}: nodes = \"{reference}\" names no node group; {}",
            ref_hint(mesh, reference)
        ))
    })
}

/// `[[point]]` bodies: mass, force and seabed stiffness go to the structure; volume and drag
/// area to the water loads (returned).
fn point_bodies(scene: &Scene, mesh: &Mesh, b: &mut ModelBuilder) -> Result<Vec<PointElement>> {
    let file = scene.path.display().to_string();
    let mut hydro_points = Vec::new();
    for (i, p) in scene.point.iter().enumerate() {
        let at = format!("{file}: line {}: [[point]] #{}", p.line, i + 1);
        let nodes = node_group(mesh, &at, &p.value.nodes)?;
        let v = &p.value;
        for n in nodes {
            if v.mass > 0.0 || v.force != [0.0; 3] || v.seabed_stiffness > 0.0 {
                b.add_point_body(PointBody {
                    node: n,
                    mass: v.mass,
                    force: v.force,
                    seabed_stiffness: v.seabed_stiffness,
                })
                .map_err(|e| SimError::at(at.clone(), e))?;
            }
            if v.volume > 0.0 || v.drag_area > 0.0 {
                hydro_points.push(PointElement {
                    node: n,
                    props: PointProps {
                        volume: v.volume,
                        shape: PointShape::Prism { height: v.height },
                        drag_area: v.drag_area,
                        added_mass: v.added_mass_coefficient,
                    },
                });
            }
        }
    }
    Ok(hydro_points)
}

/// The builders' fixed groups (all DOFs) and `[[fix]]` (the listed DOFs); returns the supported
/// nodes and the clamped ones (`clamp = true`).
fn fixed_nodes(
    scene: &Scene,
    mesh: &Mesh,
    b: &mut ModelBuilder,
) -> Result<(BTreeSet<usize>, BTreeSet<usize>)> {
    let file = scene.path.display().to_string();
    let mut supported = BTreeSet::new();
    let mut clamped = BTreeSet::new();
    for n in mesh.fixed_nodes() {
        b.fix(n, Dofs::ALL)
            .map_err(|e| SimError::at(format!("{file}: fixed node"), e))?;
        supported.insert(n);
    }
    for (i, f) in scene.fix.iter().enumerate() {
        let at = format!("{file}: line {}: [[fix]] #{}", f.line, i + 1);
        let nodes = node_group(mesh, &at, &f.value.nodes)?;
        let has = |d: &str| f.value.dofs.iter().any(|x| x == d);
        let dofs = Dofs {
            x: has("x"),
            y: has("y"),
            z: has("z"),
        };
        if f.value.clamp && !(dofs.x && dofs.y && dofs.z) {
            return Err(SimError::input(format!(
                "{at}: clamp = true with dofs = {:?}: a clamp holds the node's position and the \
                 pipe's rotation there, so `dofs` must hold all of \"x\", \"y\", \"z\" (leave it \
                 out)",
                f.value.dofs
            )));
        }
        for n in nodes {
            b.fix(n, dofs).map_err(|e| SimError::at(at.clone(), e))?;
            supported.insert(n);
            if f.value.clamp {
                clamped.insert(n);
            }
        }
    }
    Ok((supported, clamped))
}

/// `[[prescribed]]` motions (docs/theory/fem.md#boundary-conditions), or external ones for a
/// coupling.
#[allow(clippy::type_complexity)]
fn prescribed_motions(
    scene: &Scene,
    mesh: &Mesh,
    how: Prescribed,
    b: &mut ModelBuilder,
    supported: &mut BTreeSet<usize>,
) -> Result<Vec<(String, Vec<(usize, ExternalMotion)>)>> {
    let file = scene.path.display().to_string();
    let mut external = Vec::new();
    for (i, p) in scene.prescribed.iter().enumerate() {
        let at = format!("{file}: line {}: [[prescribed]] #{}", p.line, i + 1);
        let nodes = node_group(mesh, &at, &p.value.nodes)?;
        // The scene's motion is validated even when a coupling drives the nodes.
        let m = motion(&p.value).map_err(|e| match e {
            MotionError::Missing(msg) => SimError::input(format!("{at}: {msg}")),
            MotionError::Fem(e) => SimError::at(at.clone(), e),
        })?;
        let mut driven = Vec::new();
        for n in nodes {
            let m = match how {
                Prescribed::AsScene => m.clone(),
                Prescribed::External => {
                    let e = ExternalMotion::at_rest();
                    driven.push((n, e.clone()));
                    Motion::External(e)
                }
            };
            b.prescribe(n, m).map_err(|e| SimError::at(at.clone(), e))?;
            supported.insert(n);
        }
        if how == Prescribed::External {
            external.push((p.value.nodes.clone(), driven));
        }
    }
    Ok(external)
}

enum MotionError {
    Missing(String),
    Fem(aqua_fem::FemError),
}

impl From<aqua_fem::FemError> for MotionError {
    fn from(e: aqua_fem::FemError) -> Self {
        Self::Fem(e)
    }
}

/// The aqua-fem motion of a `[[prescribed]]` table.
fn motion(p: &PrescribedSpec) -> std::result::Result<Motion, MotionError> {
    let missing = |what: &str| MotionError::Missing(what.to_string());
    let need3 = |v: Option<[f64; 3]>, key: &str| {
        v.ok_or_else(|| {
            missing(
                &format!(
                    "{key} = [x, y, z] (m) is required for motion = \"{:?}\"",
                    p.motion
                )
                .to_lowercase(),
            )
        })
    };
    let m = match p.motion {
        // Held at the as-built place until a coupling drives it (aqua-sim run refuses it).
        MotionKind::Coupled => {
            let given = [
                ("offset", p.offset.is_some()),
                ("amplitude", p.amplitude.is_some()),
                ("mean", p.mean.is_some()),
                ("period", p.period.is_some()),
                ("phase", p.phase != 0.0),
                ("ramp_time", p.ramp_time.is_some()),
                ("table", p.table.is_some()),
            ];
            if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
                return Err(missing(&format!(
                    "{key} is not used by motion = \"coupled\" (the coupling gives the \
                     motion); remove it"
                )));
            }
            Motion::Constant([0.0; 3])
        }
        MotionKind::Constant => Motion::Constant(need3(p.offset, "offset")?),
        MotionKind::Ramp => Motion::Ramp {
            target: need3(p.offset, "offset")?,
            duration: p
                .ramp_time
                .ok_or_else(|| missing("ramp_time (s) is required for motion = \"ramp\""))?,
        },
        MotionKind::Sine => Motion::harmonic(
            need3(p.amplitude, "amplitude")?,
            p.mean.unwrap_or([0.0; 3]),
            p.period
                .ok_or_else(|| missing("period (s) is required for motion = \"sine\""))?,
            p.phase.to_radians(),
            p.ramp_time.unwrap_or(0.0),
        )?,
        MotionKind::Table => Motion::table(p.table.as_deref().ok_or_else(|| {
            missing("table = [[t, dx, dy, dz], ...] is required for motion = \"table\"")
        })?)?,
    };
    Ok(m)
}
