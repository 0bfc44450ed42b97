//! From a scene to what the solvers need: scene → mesh → structural model + sea + water loads.
//!
//! [`build`] runs the steps in that order, each a function named after what it builds:
//! [`build_mesh`] (the merged mesh), [`build_sea`] (the sea, its irregular band weighted at
//! the structure's top), `build_structure` (aqua-fem model), `build_water_loads` (aqua-hydro
//! elements) and [`find_line_ends`] (what the outputs report per `[[line]]`).

mod bending;
mod bodies;
mod buoys;
mod mesh;
mod partition;
mod structure;
mod water;

pub use mesh::{BuiltFarm, build_mesh, resolve_ref};
pub use structure::Prescribed;
pub use water::LoadCell;

use crate::design::{DesignChecks, LineLength};
use crate::diagnostic::Diagnostic;
use crate::error::{Result, SimError};
use crate::scene::{AnalysisKind, Scene};
use aqua_env::{BuildOptions, Sea, SeaSummary};
use aqua_fem::{ExternalMotion, Model};
use aqua_hydro::CageWake;
use aqua_hydro::assembly::{Elements, PointElement};
use aqua_mesh::{LineElement, Mesh, ObjectKind};
use std::sync::Arc;

/// Everything a run needs, built from a scene.
#[derive(Debug)]
pub struct Built {
    /// The merged mesh (as built).
    pub mesh: Mesh,
    /// The structural model; node i is mesh node i, element e is mesh line e.
    pub model: Model,
    /// Hydro load elements (built into a `LoadAssembly` by the caller).
    pub elements: Elements,
    /// The sea.
    pub sea: Arc<Sea>,
    /// Its summary.
    pub sea_summary: SeaSummary,
    /// Per mesh line: true if it is a net twine.
    pub is_twine: Vec<bool>,
    /// Per mesh panel: true if it carries screen loads.
    pub panel_loaded: Vec<bool>,
    /// Per panel and line load element (assembly order): its mesh cell.
    pub load_cells: Vec<LoadCell>,
    /// Names of the structural groups: the cable groups (index = fem group id), then the net
    /// triangle groups (index − cable groups = net triangle group id).
    pub group_names: Vec<String>,
    /// Nodes with fixed or prescribed DOFs.
    pub supported_nodes: Vec<usize>,
    /// Net panels grouped per net (object, copy) for the enclosed-volume output.
    pub nets: Vec<NetCells>,
    /// Per `[[line]]`: name, anchor node, fairlead node, first and last element.
    pub line_ends: Vec<LineEnds>,
    /// The farms: buoys, cages, anchor lines and counts per part.
    pub farms: Vec<BuiltFarm>,
    /// The cage-to-cage wake (docs/theory/hydrodynamics.md#cage-to-cage-wake): the cages of
    /// farms with `cage_wake` and, with `[wake] cage_to_cage`, every `[[cage]]` copy.
    pub cage_wake: CageWake,
    /// Externally driven nodes (built with [`Prescribed::External`]): the `[[prescribed]]`
    /// node reference, its nodes and their motions.
    pub external: Vec<(String, Vec<(usize, ExternalMotion)>)>,
    /// Warnings collected while building (mesh, sea, design).
    pub diagnostics: Vec<Diagnostic>,
    /// What the design checks look at after statics (docs/theory/farm.md#design-warnings).
    pub design: DesignChecks,
    /// The groups of pipes modelled as rods, whose stresses are reported
    /// (docs/theory/fem.md#rod).
    pub pipes: Vec<crate::pipe_stress::PipeGroup>,
    /// Per mesh panel: its net triangle in the model, if it is one
    /// (docs/theory/fem.md#net-triangle).
    pub panel_triangle: Vec<Option<usize>>,
}

/// The two ends of a single line (docs/theory/fem.md#outputs: report end reactions and end-element
/// tensions).
#[derive(Debug, Clone)]
pub struct LineEnds {
    /// Line object name.
    pub name: String,
    /// Anchor node.
    pub anchor: usize,
    /// Fairlead node.
    pub fairlead: usize,
    /// Element at the anchor.
    pub anchor_element: usize,
    /// Element at the fairlead.
    pub fairlead_element: usize,
    /// Whether the anchor and the fairlead node are fixed or prescribed (their `_reaction` is
    /// the support's force); a free end, attached to another structure, reports the pull of
    /// its end element instead (docs/theory/fem.md#outputs).
    pub supported: [bool; 2],
}

/// The panels of one net (one cage copy, panel or gmsh net).
#[derive(Debug, Clone)]
pub struct NetCells {
    /// Object name and copy.
    pub name: String,
    /// Mesh panel ids.
    pub panels: Vec<usize>,
    /// True if the net encloses a volume (cages).
    pub closed: bool,
}

/// Builds the whole model of a scene; `prescribed` says who moves the prescribed nodes.
pub fn build(scene: &Scene, prescribed: Prescribed) -> Result<Built> {
    let file = scene.path.display().to_string();
    // Sea errors first: they are independent of the structure (the real build needs the
    // structure's top for the irregular band).
    scene
        .sea
        .build(&BuildOptions::default())
        .map_err(|e| SimError::at(file.clone(), e))?;
    let mesh::MeshParts { mesh, nets, farms } = mesh::build_mesh_parts(scene)?;
    let (sea, sea_summary) = build_sea(scene, &mesh)?;
    if let Some(h) = sea.constants().depth.finite() {
        below_seabed(&mesh, h).map_err(|m| SimError::input(format!("{file}: {m}")))?;
    }
    let env = structure::environment(scene, sea.constants());
    let mut st = structure::build_structure(scene, &mesh, env, prescribed)?;
    add_buoys(&file, &farms, &mut st)?;
    let mut model = st
        .builder
        .build()
        .map_err(|e| SimError::at(file.clone(), e))?;
    model
        .set_partition(partition::cage_partition(&mesh))
        .map_err(|e| SimError::at(file, e))?;
    let wake_cages = cage_wake_objects(scene, &mesh, &farms);
    let loads = water::build_water_loads(
        scene,
        &mesh,
        &nets,
        &st.sections,
        st.hydro_points,
        &wake_cages,
    )?;
    // A gmsh line group's "uses the rope default section" notice is moot once a `[[group]]`
    // sets its section.
    let notices: Vec<String> = mesh
        .notices
        .iter()
        .filter(|n| !section_set_by_group(scene, n))
        .cloned()
        .collect();
    let mut diagnostics = Diagnostic::warnings("mesh/notice", "mesh", &notices);
    diagnostics.extend(Diagnostic::warnings(
        "sea/range",
        "sea",
        &sea_summary.warnings,
    ));
    let line_ends = find_line_ends(&mesh);
    let mut floaters = st.buoys;
    // Buoys and the points rigid bodies hold carry a line's end.
    let mut carried: Vec<usize> = floaters.iter().flat_map(|f| f.nodes.clone()).collect();
    carried.extend(
        model
            .rigid_bodies()
            .iter()
            .flat_map(|b| b.points.iter().map(|p| p.0)),
    );
    for le in &line_ends {
        let oi = mesh.objects.iter().position(|o| o.name == le.name);
        for (end, nd) in [("anchor", le.anchor), ("fairlead", le.fairlead)] {
            if carried.contains(&nd) {
                continue;
            }
            if let Some(msg) = oi.and_then(|oi| free_line_end(&mesh, &model, oi, &le.name, end, nd))
            {
                diagnostics.push(Diagnostic::warning("line/free-end", &le.name, msg));
            }
        }
    }
    // The midpoint rule keeps the rigid links' stiff modes undamped
    // (docs/theory/farm.md#rigid-bodies).
    if scene.analysis.kind != crate::scene::AnalysisKind::Static
        && scene.analysis.dynamic.scheme == crate::scene::Scheme::Midpoint
    {
        for b in model.rigid_bodies() {
            diagnostics.push(Diagnostic::warning(
                "fem/body-scheme",
                &b.name,
                format!(
                    "body '{}' with scheme = \"midpoint\": the rule leaves the stiff modes of the \
                     links that hold its points undamped, and on the bundled feed barge in waves \
                     its fairlead peaks were 66 % high at dt 0.1 s (docs/theory/farm.md#rigid-bodies); \
                     use scheme = \"hht\" (the default)",
                    b.name
                ),
            ));
        }
    }
    let held = |n: usize| (0..3).all(|k| model.is_constrained(n, k));
    floaters.extend(buoys::floating_pipes(
        &mesh,
        &st.sections,
        model.environment().water_density,
        &held,
    ));
    let design = DesignChecks {
        floaters,
        lines: line_lengths(&mesh, &line_ends),
        seabed_z: model.environment().seabed.as_ref().map(|s| -s.depth),
        kinks: model
            .point_bodies()
            .iter()
            .map(|b| b.node)
            .chain(carried)
            .collect(),
        nets: net_nodes(&mesh),
    };
    diagnostics.extend(design.as_built(&mesh.nodes));
    diagnostics.extend(crate::design::coarse_nets(&mesh));
    diagnostics.extend(crate::design::sinker_tubes(
        &mesh,
        &st.sections,
        model.environment().water_density,
        model.environment().gravity,
    ));
    let supported_nodes: Vec<usize> = st.supported.into_iter().collect();
    let pipes = crate::pipe_stress::pipe_groups(&st.sections, &st.group_names, &model);
    let mut line_ends = line_ends;
    for le in &mut line_ends {
        le.supported = [le.anchor, le.fairlead].map(|n| supported_nodes.contains(&n));
    }
    Ok(Built {
        mesh,
        model,
        elements: loads.elements,
        sea: Arc::new(sea),
        sea_summary,
        is_twine: loads.is_twine,
        panel_loaded: loads.panel_loaded,
        load_cells: loads.load_cells,
        group_names: st.group_names,
        supported_nodes,
        nets: loads.nets,
        line_ends,
        farms,
        cage_wake: loads.cage_wake,
        external: st.external,
        diagnostics,
        design,
        pipes,
        panel_triangle: st.panel_triangle,
    })
}

/// The farms' buoys as point bodies: mass to the structure, volume and drag to the water
/// loads (as a `[[point]]` on the buoy node).
fn add_buoys(file: &str, farms: &[BuiltFarm], st: &mut structure::Structure) -> Result<()> {
    for f in farms {
        for &node in &f.buoys {
            if f.buoy.mass > 0.0 {
                st.builder
                    .add_point_body(aqua_fem::PointBody {
                        node,
                        mass: f.buoy.mass,
                        force: [0.0; 3],
                        seabed_stiffness: 0.0,
                    })
                    .map_err(|e| {
                        SimError::at(
                            format!("{file}: line {}: [[farm]] {} buoy", f.line, f.name),
                            e,
                        )
                    })?;
            }
            if let Some(props) = f.buoy.props {
                st.hydro_points.push(PointElement { node, props });
            }
        }
    }
    Ok(())
}

/// The cage objects that take part in the cage-to-cage wake.
fn cage_wake_objects(
    scene: &Scene,
    mesh: &Mesh,
    farms: &[BuiltFarm],
) -> std::collections::HashSet<String> {
    let mut set: std::collections::HashSet<String> = farms
        .iter()
        .filter(|f| f.cage_wake)
        .flat_map(|f| f.cages.iter().cloned())
        .collect();
    if scene.wake.cage_to_cage {
        let in_farm: std::collections::HashSet<&String> =
            farms.iter().flat_map(|f| &f.cages).collect();
        set.extend(
            mesh.objects
                .iter()
                .filter(|o| matches!(o.kind, ObjectKind::Cage(_)) && !in_farm.contains(&o.name))
                .map(|o| o.name.clone()),
        );
    }
    set
}

/// The sea of a scene, its irregular band weighted at the shallowest node
/// (docs/theory/environment.md#choosing-the-frequency-band). The current ramps in only when
/// dynamics starts without a static state that has it.
pub fn build_sea(scene: &Scene, mesh: &Mesh) -> Result<(Sea, SeaSummary)> {
    let z_top = mesh
        .nodes
        .iter()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let kind = scene.analysis.kind;
    let opts = BuildOptions {
        z_ref: z_top.min(0.0),
        duration: (kind != AnalysisKind::Static).then_some(scene.analysis.dynamic.t_end),
    };
    let (sea, summary) = scene
        .sea
        .build(&opts)
        .map_err(|e| SimError::at(scene.path.display().to_string(), e))?;
    let ramp = kind == AnalysisKind::Dynamic || !scene.sea.current.in_static;
    Ok((sea.with_current_ramp(ramp), summary))
}

/// A line end that nothing holds: not fixed or prescribed in any DOF, and no element or panel
/// of another object uses it. Statics would let such a line fall and lie on the seabed with a
/// zero end force, which is almost never what the user meant.
fn free_line_end(
    mesh: &Mesh,
    model: &aqua_fem::Model,
    object: usize,
    line: &str,
    end: &str,
    node: usize,
) -> Option<String> {
    if (0..3).any(|k| model.is_constrained(node, k)) {
        return None;
    }
    let other_line = mesh
        .lines
        .iter()
        .any(|e| e.object as usize != object && e.nodes.contains(&node));
    let other_panel = mesh
        .panels
        .iter()
        .any(|p| p.nodes.as_slice().contains(&node));
    if other_line || other_panel {
        return None;
    }
    let fall = if model.environment().seabed.is_some() {
        "fall to the seabed"
    } else {
        "sink or float with nothing to hold it (the sea has no seabed)"
    };
    // Only a fairlead can name a node of another object; an anchor is a position.
    let fix = if end == "fairlead" {
        "Add \"fairlead\" to the line's `fixed`, give it a [[prescribed]] motion, or set \
         `fairlead` to a node such as \"cage0/top_ring[0]\""
    } else {
        "Add \"anchor\" to the line's `fixed` or give it a [[prescribed]] motion"
    };
    Some(format!(
        "line '{line}': its {end} is neither fixed, prescribed nor attached to another object; \
         the line will {fall} with a zero {end} force. {fix}"
    ))
}

/// The ends and unstretched length (the sum over its elements) of every `[[line]]`.
fn line_lengths(mesh: &Mesh, line_ends: &[LineEnds]) -> Vec<LineLength> {
    line_ends
        .iter()
        .filter_map(|le| {
            let oi = mesh.objects.iter().position(|o| o.name == le.name)? as u32;
            let elements: Vec<&LineElement> =
                mesh.lines.iter().filter(|l| l.object == oi).collect();
            let unstretched = elements
                .iter()
                .map(|l| l.rest_length)
                .sum::<Option<f64>>()?;
            Some(LineLength {
                name: le.name.clone(),
                anchor: le.anchor,
                fairlead: le.fairlead,
                unstretched,
                path: node_path(&elements, le.anchor, le.fairlead),
            })
        })
        .collect()
}

/// The nodes of a line from `anchor` to `fairlead` when its elements form one unbranched
/// chain between them; empty otherwise.
fn node_path(elements: &[&LineElement], anchor: usize, fairlead: usize) -> Vec<usize> {
    let mut path = vec![anchor];
    let mut used = vec![false; elements.len()];
    while path.len() <= elements.len() {
        let here = path[path.len() - 1];
        let next = elements.iter().enumerate().find_map(|(i, e)| {
            let other = match e.nodes {
                [a, b] if a == here => b,
                [a, b] if b == here => a,
                _ => return None,
            };
            (!used[i]).then_some((i, other))
        });
        let Some((i, node)) = next else { break };
        used[i] = true;
        path.push(node);
    }
    if path.len() == elements.len() + 1 && path.last() == Some(&fairlead) {
        path
    } else {
        Vec::new()
    }
}

/// The nodes of every cage and panel object, by object name.
fn net_nodes(mesh: &Mesh) -> Vec<(String, Vec<usize>)> {
    let mut nets: Vec<(String, Vec<usize>)> = Vec::new();
    for (oi, obj) in mesh.objects.iter().enumerate() {
        if matches!(obj.kind, ObjectKind::Cage(_) | ObjectKind::Panel) {
            let nodes = (0..mesh.nodes.len())
                .filter(|&n| mesh.node_owner.get(n).is_some_and(|o| o.0 == oi as u32))
                .collect();
            nets.push((obj.name.clone(), nodes));
        }
    }
    nets
}

/// How far below the seabed z = −h an as-built node may lie (round-off of a builder's
/// anchor or laid chain) [m]: 1e-3·h.
const BELOW_SEABED_TOLERANCE: f64 = 1e-3;

/// An object whose as-built geometry lies below the seabed z = −h [m] by more than
/// [`BELOW_SEABED_TOLERANCE`]·h (the penalty bed would throw it up, or a cage was made deeper
/// than the sea).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "'{object}' reaches below the seabed as built: its lowest node is at z = {lowest:.3} m, the \
     seabed at z = {seabed:.3} m (sea.depth = {depth}); {count} node(s) lie below it. Make the \
     structure shallower (a cage's depth and cone, a line's anchor) or the sea deeper"
)]
struct BelowSeabed {
    /// The object of the lowest node.
    object: String,
    /// z of the lowest node [m].
    lowest: f64,
    /// z of the seabed, −h [m].
    seabed: f64,
    /// The water depth h [m].
    depth: f64,
    /// Nodes below the seabed.
    count: usize,
}

/// [`BelowSeabed`] for the object of the lowest node below the seabed z = −h, if any.
fn below_seabed(mesh: &Mesh, h: f64) -> std::result::Result<(), BelowSeabed> {
    let tol = BELOW_SEABED_TOLERANCE * h;
    let lowest = (0..mesh.nodes.len())
        .filter(|&n| mesh.nodes[n].z < -h - tol)
        .min_by(|&a, &b| mesh.nodes[a].z.total_cmp(&mesh.nodes[b].z));
    let Some(n) = lowest else { return Ok(()) };
    let object = mesh
        .node_owner
        .get(n)
        .and_then(|&(o, _)| mesh.objects.get(o as usize))
        .map(|o| o.name.as_str())
        .unwrap_or("?");
    Err(BelowSeabed {
        object: object.to_string(),
        lowest: mesh.nodes[n].z,
        seabed: -h,
        depth: h,
        count: mesh.nodes.iter().filter(|p| p.z < -h - tol).count(),
    })
}

/// Anchor and fairlead nodes and end elements of every `[[line]]` object.
pub fn find_line_ends(mesh: &Mesh) -> Vec<LineEnds> {
    let mut line_ends = Vec::new();
    for (oi, obj) in mesh.objects.iter().enumerate() {
        if !matches!(obj.kind, ObjectKind::Line) {
            continue;
        }
        let node = |g: &str| {
            mesh.groups
                .iter()
                .find(|x| x.object == oi as u32 && x.name == g)
                .and_then(|x| x.nodes.first().copied())
        };
        let mut elems = (0..mesh.lines.len()).filter(|&e| mesh.lines[e].object == oi as u32);
        let first = elems.next();
        let last = elems.next_back().or(first);
        if let (Some(a), Some(f), Some(first), Some(last)) =
            (node("anchor"), node("fairlead"), first, last)
        {
            line_ends.push(LineEnds {
                name: obj.name.clone(),
                anchor: a,
                fairlead: f,
                anchor_element: first,
                fairlead_element: last,
                supported: [false; 2],
            });
        }
    }
    line_ends
}

/// True if `notice` is aqua-mesh's "line group `n` uses the rope default section" for a group
/// whose section a `[[group]]` (`n` or `object/n`) sets.
fn section_set_by_group(scene: &Scene, notice: &str) -> bool {
    let Some(rest) = notice.strip_prefix("notice: ") else {
        return false;
    };
    let Some((obj, rest)) = rest.split_once(": line group `") else {
        return false;
    };
    let Some((group, _)) = rest.split_once("` uses the rope default section") else {
        return false;
    };
    scene.group.iter().any(|g| {
        let g = &g.value;
        (g.name == group || g.name == format!("{obj}/{group}"))
            && g.section != aqua_mesh::SectionOverride::default()
    })
}
