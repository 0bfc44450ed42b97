//! From a scene to what the solvers need: scene → mesh → structural model + sea + water loads.
//!
//! - The mesh is the union of every `[[cage]]`, `[[panel]]`, `[[mesh]]` and `[[line]]`; a line
//!   whose fairlead names a node of another object is welded to that node.
//! - The structural model (aqua-fem) gets one cable group per mesh line group
//!   ("object/group"), point masses from the builders' weights and `[[point]]`, fixed nodes
//!   from the builders' `fixed` groups and `[[fix]]`, and `[[prescribed]]` motions.
//! - The water loads (aqua-hydro) get screen panels, Morison lines (net twines with their
//!   volume/hydrodynamic diameters), point bodies, and one wake group per cage copy.

use crate::InputError;
use crate::scene::{
    GroupSpec, LineHydro, Located, MotionKind, NetDrag, NetHydro, PrescribedSpec, Scene,
};
use aqua_env::{BuildOptions, Depth, Sea, SeaSummary};
use aqua_fem::{
    AxialDamping, CableSection, Dofs, Environment, Model, ModelBuilder, Motion, PointBody, Seabed,
    UnstretchedLength,
};
use aqua_hydro::assembly::{
    Elements, LineElement as HydroLine, NetPanel, PanelNodes as HydroPanelNodes, PointElement,
    WakeGroup,
};
use aqua_hydro::{
    LineProps, MorisonModel, MorisonModelId, NetProps, PointProps, ScreenModel, Wake, WakeModelId,
    WakeSpec, WakeUpdate,
};
use aqua_mesh::{Fairlead, Mesh, ObjectKind, PanelNodes, Role, Section};
use std::collections::{BTreeMap, HashMap};
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
    /// Its summary and warnings.
    pub sea_summary: SeaSummary,
    /// Per mesh line: true if it is a net twine.
    pub is_twine: Vec<bool>,
    /// Per mesh panel: true if it carries screen loads.
    pub panel_loaded: Vec<bool>,
    /// Names of the structural groups (index = fem group id).
    pub group_names: Vec<String>,
    /// Nodes with fixed or prescribed DOFs.
    pub supported_nodes: Vec<usize>,
    /// Net panels grouped per net (object, copy) for the enclosed-volume output.
    pub nets: Vec<NetCells>,
    /// Per `[[line]]`: name, anchor node, fairlead node, first and last element.
    pub line_ends: Vec<LineEnds>,
    /// Warnings and notices collected while building.
    pub notices: Vec<String>,
}

/// The two ends of a single line (fem.md §14: report end reactions and end-element tensions).
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

fn input(msg: impl Into<String>) -> InputError {
    InputError::new(msg.into())
}

/// Resolves "object/group[k]" (or without `[k]`) to node ids.
pub fn resolve_ref(mesh: &Mesh, reference: &str) -> Option<Vec<usize>> {
    if let Some(open) = reference.rfind('[')
        && reference.ends_with(']')
    {
        let k: usize = reference[open + 1..reference.len() - 1]
            .trim()
            .parse()
            .ok()?;
        let nodes = mesh.resolve_nodes(&reference[..open])?;
        return nodes.get(k).map(|n| vec![*n]);
    }
    mesh.resolve_nodes(reference)
}

fn group_names_hint(mesh: &Mesh) -> String {
    let mut names: Vec<String> = mesh
        .groups
        .iter()
        .filter(|g| !g.nodes.is_empty())
        .map(|g| format!("{}/{}", mesh.objects[g.object as usize].name, g.name))
        .collect();
    names.sort();
    names.dedup();
    if names.len() > 30 {
        names.truncate(30);
        names.push("…".into());
    }
    names.join(", ")
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
    Some(format!(
        "line '{line}': its {end} is neither fixed, prescribed nor attached to another object; \
         the line will fall to the seabed with a zero {end} force. Add \"{end}\" to the line's \
         `fixed`, give it a [[prescribed]] motion, or set `fairlead` to a node such as \
         \"cage0/top_ring[0]\""
    ))
}

/// Merges the last node of the mesh into `target` (a line's fairlead onto an existing node).
fn weld_last_node(mesh: &mut Mesh, target: usize) {
    let dup = mesh.nodes.len() - 1;
    mesh.nodes.pop();
    mesh.node_owner.pop();
    let map = |n: &mut usize| {
        if *n == dup {
            *n = target;
        }
    };
    for l in &mut mesh.lines {
        l.nodes.iter_mut().for_each(map);
    }
    for p in &mut mesh.panels {
        match &mut p.nodes {
            PanelNodes::Tri(n) => n.iter_mut().for_each(map),
            PanelNodes::Quad(n) => n.iter_mut().for_each(map),
        }
    }
    for g in &mut mesh.groups {
        g.nodes.iter_mut().for_each(map);
        g.nodes.sort_unstable();
        g.nodes.dedup();
    }
    for w in &mut mesh.weights {
        map(&mut w.node);
    }
}

fn default_name(given: &Option<String>, kind: &str, i: usize) -> String {
    given.clone().unwrap_or_else(|| format!("{kind}{i}"))
}

/// Builds the merged mesh of a scene.
pub fn build_mesh(scene: &Scene) -> Result<(Mesh, HashMap<String, NetHydro>), InputError> {
    let file = scene.path.display().to_string();
    let seabed_z = scene.sea.depth.as_ref().and_then(|_| {
        scene
            .sea
            .constants()
            .ok()
            .and_then(|c| c.depth.finite())
            .map(|h| -h)
    });
    let mut mesh = Mesh::default();
    let mut nets: HashMap<String, NetHydro> = HashMap::new();
    let mut names: BTreeMap<String, usize> = BTreeMap::new();
    let mut check_name = |name: &str, line: usize| -> Result<(), InputError> {
        if let Some(prev) = names.insert(name.to_string(), line) {
            return Err(input(format!(
                "{file}: line {line}: object name \"{name}\" is already used by the object at line {prev}; give each object a unique name"
            )));
        }
        Ok(())
    };
    for (i, c) in scene.cage.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = default_name(&p.name, "cage", i);
        check_name(&name, c.line)?;
        p.name = Some(name.clone());
        let m = p
            .build()
            .map_err(|e| input(format!("{file}: line {}: [[cage]] #{}: {e}", c.line, i + 1)))?;
        mesh.append(m);
        nets.insert(name, c.value.net_hydro.clone());
    }
    for (i, c) in scene.panel.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = default_name(&p.name, "panel", i);
        check_name(&name, c.line)?;
        p.name = Some(name.clone());
        if let Some(w) = &c.value.net_hydro.wake
            && w.model != WakeModelId::None
        {
            return Err(input(format!(
                "{file}: line {}: [[panel]] #{}: net.wake.model = \"{}\": a single flat panel has no downstream net; only \"none\" is valid",
                c.line,
                i + 1,
                w.model
            )));
        }
        let m = p.build().map_err(|e| {
            input(format!(
                "{file}: line {}: [[panel]] #{}: {e}",
                c.line,
                i + 1
            ))
        })?;
        mesh.append(m);
        nets.insert(name, c.value.net_hydro.clone());
    }
    for (i, c) in scene.mesh.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = default_name(&p.name, "mesh", i);
        check_name(&name, c.line)?;
        p.name = Some(name.clone());
        let m = aqua_mesh::import_gmsh(&p)
            .map_err(|e| input(format!("{file}: line {}: [[mesh]] #{}: {e}", c.line, i + 1)))?;
        mesh.append(m);
        nets.insert(name, c.value.net_hydro.clone());
    }
    for (i, c) in scene.line.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = default_name(&p.name, "line", i);
        check_name(&name, c.line)?;
        p.name = Some(name.clone());
        let mut weld_to = None;
        let mut fair_pos = None;
        if let Some(Fairlead::Node(r)) = &p.fairlead {
            let nodes = resolve_ref(&mesh, r).ok_or_else(|| {
                input(format!(
                    "{file}: line {}: [[line]] #{}: fairlead = \"{r}\" names no node; use \"object/group[k]\" with one of: {}",
                    c.line,
                    i + 1,
                    group_names_hint(&mesh)
                ))
            })?;
            if nodes.len() != 1 {
                return Err(input(format!(
                    "{file}: line {}: [[line]] #{}: fairlead = \"{r}\" names {} nodes; pick one with [k], e.g. \"{r}[0]\"",
                    c.line,
                    i + 1,
                    nodes.len()
                )));
            }
            let n = nodes[0];
            let x = mesh.nodes[n];
            fair_pos = Some([x.x, x.y, x.z]);
            weld_to = Some(n);
        }
        let m = p
            .build_with(fair_pos, seabed_z)
            .map_err(|e| input(format!("{file}: line {}: [[line]] #{}: {e}", c.line, i + 1)))?;
        mesh.append(m);
        if let Some(target) = weld_to {
            weld_last_node(&mut mesh, target);
        }
    }
    if mesh.nodes.is_empty() {
        return Err(input(format!(
            "{file}: the scene has no structure: add a [[cage]], [[panel]], [[line]] or [[mesh]]"
        )));
    }
    Ok((mesh, nets))
}

fn section_of(mesh: &Mesh, group: usize) -> Option<&Section> {
    mesh.groups[group].section.as_ref()
}

/// The `[[group]]` entry for a mesh group: "object/group" first, then "group".
fn group_spec<'a>(scene: &'a Scene, object: &str, group: &str) -> Option<&'a Located<GroupSpec>> {
    let full = format!("{object}/{group}");
    scene
        .group
        .iter()
        .find(|g| g.value.name == full)
        .or_else(|| scene.group.iter().find(|g| g.value.name == group))
}

fn motion(p: &PrescribedSpec) -> Result<Motion, String> {
    let need3 = |v: Option<[f64; 3]>, key: &str| {
        v.ok_or_else(|| {
            format!(
                "{key} = [x, y, z] (m) is required for motion = \"{:?}\"",
                p.motion
            )
            .to_lowercase()
        })
    };
    let m = match p.motion {
        MotionKind::Constant => Motion::Constant(need3(p.offset, "offset")?),
        MotionKind::Ramp => Motion::Ramp {
            target: need3(p.offset, "offset")?,
            duration: p
                .ramp_time
                .ok_or("ramp_time (s) is required for motion = \"ramp\"")?,
        },
        MotionKind::Sine => Motion::harmonic(
            need3(p.amplitude, "amplitude")?,
            p.mean.unwrap_or([0.0; 3]),
            p.period
                .ok_or("period (s) is required for motion = \"sine\"")?,
            p.phase.to_radians(),
            p.ramp_time.unwrap_or(0.0),
        )
        .map_err(|e| e.to_string())?,
        MotionKind::Table => Motion::table(
            p.table
                .as_deref()
                .ok_or("table = [[t, dx, dy, dz], ...] is required for motion = \"table\"")?,
        )
        .map_err(|e| e.to_string())?,
    };
    Ok(m)
}

/// Builds the whole model of a scene.
pub fn build(scene: &Scene) -> Result<Built, InputError> {
    let file = scene.path.display().to_string();
    // Sea errors first: they are independent of the structure (the real build below needs
    // the structure's top for the irregular band).
    scene
        .sea
        .build(&BuildOptions::default())
        .map_err(|e| input(format!("{file}: {e}")))?;
    let (mesh, nets) = build_mesh(scene)?;
    let mut notices = mesh.notices.clone();

    // The sea, with the band weighting at the shallowest node.
    let z_top = mesh
        .nodes
        .iter()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let dynamic = scene.analysis.kind != crate::scene::AnalysisKind::Static;
    let opts = BuildOptions {
        z_ref: z_top.min(0.0),
        duration: dynamic.then_some(scene.analysis.dynamic.t_end),
    };
    let (sea, sea_summary) = scene
        .sea
        .build(&opts)
        .map_err(|e| input(format!("{file}: {e}")))?;
    // The current ramps only when dynamics starts without a static state that has it.
    let sea = sea.with_current_ramp(
        scene.analysis.kind == crate::scene::AnalysisKind::Dynamic || !scene.sea.current.in_static,
    );
    let constants = *sea.constants();

    // Structural model.
    let env = Environment {
        gravity: constants.gravity,
        water_density: constants.density,
        seabed: match constants.depth {
            Depth::Finite(h) => Some(Seabed {
                depth: h,
                stiffness: scene.sea.seabed.kbot,
                damping: scene.sea.seabed.cbot,
            }),
            Depth::Infinite => None,
        },
    };
    let fem_err = |what: &str, e: aqua_fem::FemError| input(format!("{file}: {what}: {e}"));
    let mut b = ModelBuilder::new(env);
    for p in &mesh.nodes {
        b.add_node([p.x, p.y, p.z])
            .map_err(|e| fem_err("node", e))?;
    }
    // Cable groups, with [[group]] section overrides applied.
    let mut fem_group = vec![None; mesh.groups.len()];
    let mut group_names = Vec::new();
    let mut used_group_specs = vec![false; scene.group.len()];
    for (gi, g) in mesh.groups.iter().enumerate() {
        if g.lines.is_empty() {
            continue;
        }
        let object = &mesh.objects[g.object as usize].name;
        let mut section = section_of(&mesh, gi).cloned().ok_or_else(|| {
            input(format!(
                "{file}: group {object}/{} has lines but no section",
                g.name
            ))
        })?;
        if let Some(spec) = group_spec(scene, object, &g.name) {
            let k = scene
                .group
                .iter()
                .position(|s| std::ptr::eq(s, spec))
                .unwrap_or(0);
            used_group_specs[k] = true;
            spec.value
                .section
                .apply(object, &format!("group.{}", g.name), &mut section)
                .map_err(|e| {
                    input(format!(
                        "{file}: line {}: [[group]] {}: {e}",
                        spec.line, spec.value.name
                    ))
                })?;
        }
        let ea = section.axial_stiffness();
        let mu = section.linear_mass();
        let mut cs = CableSection::new(ea, mu).with_compression_ratio(section.compression_ratio);
        if let Some(c) = section.axial_damping {
            cs = cs.with_axial_damping(AxialDamping::Coefficient(c));
        } else if let Some(r) = section.axial_damping_ratio {
            cs = cs.with_axial_damping(AxialDamping::Ratio(r));
        }
        if section.seabed {
            cs = cs.with_contact(section.contact_diameter.unwrap_or(section.volume_diameter));
        }
        let name = format!("{object}/{}", g.name);
        let id = b.add_group(&name, cs).map_err(|e| fem_err(&name, e))?;
        fem_group[gi] = Some((id, section));
        group_names.push(name);
    }
    for (k, used) in used_group_specs.iter().enumerate() {
        if !used {
            let g = &scene.group[k];
            return Err(input(format!(
                "{file}: line {}: [[group]] name = \"{}\" matches no element group; valid: {}",
                g.line,
                g.value.name,
                mesh.groups
                    .iter()
                    .filter(|g| !g.lines.is_empty())
                    .map(|g| g.name.clone())
                    .collect::<std::collections::BTreeSet<_>>()
                    .into_iter()
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    for (e, l) in mesh.lines.iter().enumerate() {
        let (gid, section) = fem_group[l.group].as_ref().ok_or_else(|| {
            input(format!(
                "{file}: element {e} belongs to a group without a section"
            ))
        })?;
        let len = match l.rest_length {
            Some(l0) => UnstretchedLength::Given(l0),
            None => UnstretchedLength::AsBuilt {
                initial_tension: section.initial_tension,
            },
        };
        b.add_cable(l.nodes[0], l.nodes[1], *gid, len)
            .map_err(|err| fem_err(&format!("element {e}"), err))?;
    }
    for w in &mesh.weights {
        b.add_point_body(PointBody {
            node: w.node,
            mass: w.weight / constants.gravity,
            force: [0.0; 3],
            seabed_stiffness: 0.0,
        })
        .map_err(|e| fem_err("sinker weight", e))?;
    }
    let mut hydro_points = Vec::new();
    for (i, p) in scene.point.iter().enumerate() {
        let nodes = resolve_ref(&mesh, &p.value.nodes).ok_or_else(|| {
            input(format!(
                "{file}: line {}: [[point]] #{}: nodes = \"{}\" names no node group; valid: {}",
                p.line,
                i + 1,
                p.value.nodes,
                group_names_hint(&mesh)
            ))
        })?;
        for n in nodes {
            if p.value.mass > 0.0 || p.value.force != [0.0; 3] || p.value.seabed_stiffness > 0.0 {
                b.add_point_body(PointBody {
                    node: n,
                    mass: p.value.mass,
                    force: p.value.force,
                    seabed_stiffness: p.value.seabed_stiffness,
                })
                .map_err(|e| {
                    input(format!(
                        "{file}: line {}: [[point]] #{}: {e}",
                        p.line,
                        i + 1
                    ))
                })?;
            }
            if p.value.volume > 0.0 || p.value.drag_area > 0.0 {
                hydro_points.push(PointElement {
                    node: n,
                    props: PointProps {
                        volume: p.value.volume,
                        height: p.value.height,
                        drag_area: p.value.drag_area,
                        added_mass: p.value.added_mass_coefficient,
                    },
                });
            }
        }
    }
    // Supports.
    let mut supported = std::collections::BTreeSet::new();
    for n in mesh.fixed_nodes() {
        b.fix(n, Dofs::ALL).map_err(|e| fem_err("fixed node", e))?;
        supported.insert(n);
    }
    for (i, f) in scene.fix.iter().enumerate() {
        let nodes = resolve_ref(&mesh, &f.value.nodes).ok_or_else(|| {
            input(format!(
                "{file}: line {}: [[fix]] #{}: nodes = \"{}\" names no node group; valid: {}",
                f.line,
                i + 1,
                f.value.nodes,
                group_names_hint(&mesh)
            ))
        })?;
        let dofs = Dofs {
            x: f.value.dofs.iter().any(|d| d == "x"),
            y: f.value.dofs.iter().any(|d| d == "y"),
            z: f.value.dofs.iter().any(|d| d == "z"),
        };
        for n in nodes {
            b.fix(n, dofs)
                .map_err(|e| input(format!("{file}: line {}: [[fix]] #{}: {e}", f.line, i + 1)))?;
            supported.insert(n);
        }
    }
    for (i, p) in scene.prescribed.iter().enumerate() {
        let where_ = format!("{file}: line {}: [[prescribed]] #{}", p.line, i + 1);
        let nodes = resolve_ref(&mesh, &p.value.nodes).ok_or_else(|| {
            input(format!(
                "{where_}: nodes = \"{}\" names no node group; valid: {}",
                p.value.nodes,
                group_names_hint(&mesh)
            ))
        })?;
        let m = motion(&p.value).map_err(|e| input(format!("{where_}: {e}")))?;
        for n in nodes {
            b.prescribe(n, m.clone())
                .map_err(|e| input(format!("{where_}: {e}")))?;
            supported.insert(n);
        }
    }
    let model = b.build().map_err(|e| input(format!("{file}: {e}")))?;

    // Water loads.
    let mut wake_groups = Vec::new();
    let mut wake_index: HashMap<(u32, u32), usize> = HashMap::new();
    let mut nets_out = Vec::new();
    let hydro_err = |what: &str, e: aqua_hydro::HydroError| input(format!("{file}: {what}: {e}"));
    for (oi, obj) in mesh.objects.iter().enumerate() {
        let Some(net) = &obj.net else { continue };
        let hydro = nets.get(&obj.name).cloned().unwrap_or_default();
        let is_cage = matches!(obj.kind, ObjectKind::Cage(_));
        let spec = hydro.wake.clone().unwrap_or(WakeSpec {
            model: if is_cage {
                WakeModelId::Loland
            } else {
                WakeModelId::None
            },
            factor: None,
            cd0: None,
            update: WakeUpdate::Step,
            margin: 0.0,
            apply_to_lines: false,
        });
        let wake: Wake = spec
            .build()
            .map_err(|e| hydro_err(&format!("{} net.wake", obj.name), e))?;
        for copy in 0..obj.origins.len().max(1) as u32 {
            wake_index.insert((oi as u32, copy), wake_groups.len());
            wake_groups.push(WakeGroup {
                name: format!("{} copy {copy}", obj.name),
                wake,
                solidity: net.solidity,
            });
            nets_out.push(NetCells {
                name: if obj.origins.len() > 1 {
                    format!("{}#{copy}", obj.name)
                } else {
                    obj.name.clone()
                },
                panels: Vec::new(),
                closed: is_cage,
            });
        }
    }
    let mut panels = Vec::new();
    let mut panel_loaded = vec![false; mesh.panels.len()];
    for (pi, p) in mesh.panels.iter().enumerate() {
        let obj = &mesh.objects[p.object as usize];
        let Some(net) = &obj.net else { continue };
        let hydro = nets.get(&obj.name).cloned().unwrap_or_default();
        let wg = wake_index.get(&(p.object, p.copy)).copied();
        if let Some(w) = wg {
            nets_out[w].panels.push(pi);
        }
        if hydro.drag != NetDrag::Screen {
            continue;
        }
        let model = ScreenModel::new(hydro.screen_model, hydro.cd, hydro.cl, hydro.cyl_cd)
            .map_err(|e| hydro_err(&obj.name, e))?;
        panels.push(NetPanel {
            nodes: match p.nodes {
                PanelNodes::Tri(n) => HydroPanelNodes::Triangle(n),
                PanelNodes::Quad(n) => HydroPanelNodes::Quad(n),
            },
            net: NetProps {
                model,
                solidity: net.solidity,
                twine_diameter: net.twine_diameter,
            },
            wake_group: wg,
        });
        panel_loaded[pi] = true;
    }
    let mut lines = Vec::new();
    let mut is_twine = vec![false; mesh.lines.len()];
    let line_hydro: HashMap<String, LineHydro> = scene
        .line
        .iter()
        .enumerate()
        .map(|(i, l)| {
            (
                default_name(&l.value.params.name, "line", i),
                l.value.hydro.clone(),
            )
        })
        .collect();
    for (e, l) in mesh.lines.iter().enumerate() {
        let g = &mesh.groups[l.group];
        let obj = &mesh.objects[l.object as usize];
        let (_, section) = fem_group[l.group].as_ref().ok_or_else(|| {
            input(format!(
                "{file}: element {e} belongs to a group without a section"
            ))
        })?;
        let twine = g.role == Role::NetTwines;
        is_twine[e] = twine;
        let mut h = group_spec(scene, &obj.name, &g.name)
            .map(|s| s.value.hydro.clone())
            .unwrap_or_default();
        if let Some(inline) = line_hydro.get(&obj.name) {
            h = merge_hydro(h, inline);
        }
        let where_ = format!("{}/{}", obj.name, g.name);
        let net = obj.net.as_ref();
        let (model, knot_default, re_diameter) = if twine {
            if h.morison.is_some() {
                return Err(input(format!(
                    "{file}: [[group]] {}: a morison key on net twines is not allowed; set net.drag = \"morison\" and net.morison on the object",
                    g.name
                )));
            }
            let hydro = nets.get(&obj.name).cloned().unwrap_or_default();
            let id = if hydro.drag == NetDrag::Morison {
                hydro.morison
            } else {
                MorisonModelId::None
            };
            (
                MorisonModel::new(id, None, None, net.map(|n| n.solidity))
                    .map_err(|err| hydro_err(&where_, err))?,
                hydro.drag == NetDrag::Morison,
                net.map(|n| n.twine_diameter)
                    .unwrap_or(section.hydro_diameter),
            )
        } else {
            (
                MorisonModel::new(h.morison.unwrap_or(MorisonModelId::M4), h.cn, h.ct, None)
                    .map_err(|err| hydro_err(&where_, err))?,
                false,
                section.hydro_diameter,
            )
        };
        let l0 = l.rest_length.unwrap_or_else(|| mesh.line_length(e));
        lines.push(HydroLine {
            nodes: l.nodes,
            props: LineProps {
                model,
                hydro_diameter: section.hydro_diameter,
                reynolds_diameter: re_diameter,
                volume_diameter: section.volume_diameter,
                rest_length: l0,
                added_mass: h.added_mass.unwrap_or(1.0),
                added_mass_axial: h.added_mass_axial.unwrap_or(0.0),
                froude_krylov: h.froude_krylov.unwrap_or(true),
                knot_correction: h.knot_correction.unwrap_or(knot_default),
            },
            net_twine: twine,
            wake_group: wake_index.get(&(l.object, l.copy)).copied(),
        });
    }
    let elements = Elements {
        panels,
        lines,
        points: hydro_points,
        wake_groups,
    };
    for w in &sea_summary.warnings {
        notices.push(w.clone());
    }
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
        let elems: Vec<usize> = (0..mesh.lines.len())
            .filter(|&e| mesh.lines[e].object == oi as u32)
            .collect();
        if let (Some(a), Some(f), Some(&first), Some(&last)) = (
            node("anchor"),
            node("fairlead"),
            elems.first(),
            elems.last(),
        ) {
            for (end, nd) in [("anchor", a), ("fairlead", f)] {
                if let Some(msg) = free_line_end(&mesh, &model, oi, &obj.name, end, nd) {
                    notices.push(msg);
                }
            }
            line_ends.push(LineEnds {
                name: obj.name.clone(),
                anchor: a,
                fairlead: f,
                anchor_element: first,
                fairlead_element: last,
            });
        }
    }
    Ok(Built {
        mesh,
        model,
        elements,
        sea: Arc::new(sea),
        sea_summary,
        is_twine,
        panel_loaded,
        group_names,
        supported_nodes: supported.into_iter().collect(),
        nets: nets_out,
        line_ends,
        notices,
    })
}

/// Inline `[[line]]` keys override `[[group]]` keys.
fn merge_hydro(mut base: LineHydro, over: &LineHydro) -> LineHydro {
    if over.morison.is_some() {
        base.morison = over.morison;
    }
    if over.cn.is_some() {
        base.cn = over.cn;
    }
    if over.ct.is_some() {
        base.ct = over.ct;
    }
    if over.added_mass.is_some() {
        base.added_mass = over.added_mass;
    }
    if over.added_mass_axial.is_some() {
        base.added_mass_axial = over.added_mass_axial;
    }
    if over.froude_krylov.is_some() {
        base.froude_krylov = over.froude_krylov;
    }
    if over.knot_correction.is_some() {
        base.knot_correction = over.knot_correction;
    }
    base
}
