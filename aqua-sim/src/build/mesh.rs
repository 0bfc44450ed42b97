//! The merged mesh of a scene: every `[[cage]]`, `[[panel]]`, `[[mesh]]`, `[[farm]]`, free
//! `[[buoy]]` (one with a `position`) and `[[line]]`, with unique object names; a line whose
//! fairlead names a node of another object is welded to it.

use crate::error::{Result, SimError};
use crate::scene::{NetHydro, Scene};
use aqua_hydro::WakeModelId;
use aqua_mesh::{Fairlead, FarmCounts, Mesh};
use std::collections::{BTreeMap, HashMap};

fn input(msg: impl Into<String>) -> SimError {
    SimError::input(msg)
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

/// Why `reference` names nothing — an object part that no object's `name` has — and the
/// valid references.
pub(crate) fn ref_hint(mesh: &Mesh, reference: &str) -> String {
    let hint = group_names_hint(mesh);
    match reference.split_once('/') {
        Some((object, _)) if !mesh.objects.iter().any(|o| o.name == object) => {
            let mut objects: Vec<&str> = mesh.objects.iter().map(|o| o.name.as_str()).collect();
            objects.sort_unstable();
            format!(
                "no object has name = \"{object}\" (objects, by their `name` key or the default \
                 cage0, line0, …: {}); valid: {hint}",
                objects.join(", ")
            )
        }
        Some((object, group))
            if mesh
                .objects
                .iter()
                .any(|o| o.name == object && o.kind == aqua_mesh::ObjectKind::Body) =>
        {
            format!(
                "body '{object}' has no point with name = \"{}\" (a body's points are its \
                 [[body.point]] tables, by their `name` key, and its `hull`); valid: {hint}",
                group.split('[').next().unwrap_or(group)
            )
        }
        _ => format!("valid: {hint}"),
    }
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

pub(crate) fn default_name(given: &Option<String>, kind: &str, i: usize) -> String {
    given.clone().unwrap_or_else(|| format!("{kind}{i}"))
}

/// The mesh being merged, with the names given so far.
struct Merge {
    file: String,
    mesh: Mesh,
    nets: HashMap<String, NetHydro>,
    names: BTreeMap<String, usize>,
}

impl Merge {
    /// The object's name (given or `<kind><i>`), unique in the scene.
    fn name(
        &mut self,
        given: &Option<String>,
        kind: &str,
        i: usize,
        line: usize,
    ) -> Result<String> {
        let name = default_name(given, kind, i);
        if name.is_empty() || name.contains(['/', '[', ']']) {
            return Err(input(format!(
                "{}: line {line}: [[{kind}]] #{}: name = \"{name}\": an object name must be \
                 non-empty and without '/', '[' or ']' (nodes are named \"object/group[k]\")",
                self.file,
                i + 1
            )));
        }
        self.claim(name, line)
    }

    /// Registers an object name (given or derived), unique in the scene.
    fn claim(&mut self, name: String, line: usize) -> Result<String> {
        if let Some(prev) = self.names.insert(name.clone(), line) {
            return Err(input(format!(
                "{}: line {line}: object name \"{name}\" is already used by the object at line {prev}; give each object a unique name",
                self.file
            )));
        }
        Ok(name)
    }

    /// Appends the mesh built for object #i of `section` (header at `line`).
    fn append(
        &mut self,
        section: &str,
        i: usize,
        line: usize,
        built: std::result::Result<Mesh, aqua_mesh::MeshError>,
    ) -> Result<()> {
        let m = built.map_err(|e| {
            SimError::at(
                format!("{}: line {line}: [[{section}]] #{}", self.file, i + 1),
                e,
            )
        })?;
        self.mesh.append(m);
        Ok(())
    }
}

/// What a `[[farm]]` added to the mesh besides its objects.
#[derive(Debug, Clone)]
pub struct BuiltFarm {
    /// Farm name (the prefix of its objects).
    pub name: String,
    /// Line of its table in the scene file.
    pub line: usize,
    /// Its buoys (point bodies on mesh nodes).
    pub buoys: Vec<usize>,
    /// `[farm.buoy]`, checked: the buoy on each of `buoys`.
    pub buoy: crate::buoy::Buoy,
    /// Object names of its cages.
    pub cages: Vec<String>,
    /// Object names of its anchor lines.
    pub anchors: Vec<String>,
    /// Cage-to-cage wake among its cages.
    pub cage_wake: bool,
    /// Counts per part.
    pub counts: FarmCounts,
}

/// The merged mesh, the net keys per object and the farms.
#[derive(Debug)]
pub(crate) struct MeshParts {
    pub mesh: Mesh,
    pub nets: HashMap<String, NetHydro>,
    pub farms: Vec<BuiltFarm>,
}

/// Builds the merged mesh of a scene: cages, panels, gmsh meshes, farms, free buoys, then
/// lines (whose fairlead may name a node of the others).
pub fn build_mesh(scene: &Scene) -> Result<(Mesh, HashMap<String, NetHydro>)> {
    build_mesh_parts(scene).map(|p| (p.mesh, p.nets))
}

/// [`build_mesh`] with the farms' buoys and counts.
pub(crate) fn build_mesh_parts(scene: &Scene) -> Result<MeshParts> {
    let file = scene.path.display().to_string();
    let mut m = Merge {
        file: file.clone(),
        mesh: Mesh::default(),
        nets: HashMap::new(),
        names: BTreeMap::new(),
    };
    for (i, c) in scene.cage.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = m.name(&p.name, "cage", i, c.line)?;
        p.name = Some(name.clone());
        m.append("cage", i, c.line, p.build())?;
        m.nets.insert(name, c.value.net_hydro.clone());
    }
    for (i, c) in scene.panel.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = m.name(&p.name, "panel", i, c.line)?;
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
        m.append("panel", i, c.line, p.build())?;
        m.nets.insert(name, c.value.net_hydro.clone());
    }
    for (i, c) in scene.mesh.iter().enumerate() {
        let mut p = c.value.params.clone();
        let name = m.name(&p.name, "mesh", i, c.line)?;
        p.name = Some(name.clone());
        m.append("mesh", i, c.line, aqua_mesh::import_gmsh(&p))?;
        m.nets.insert(name, c.value.net_hydro.clone());
    }
    let mut farms = Vec::new();
    for (i, c) in scene.farm.iter().enumerate() {
        farms.push(add_farm(scene, &mut m, i, c)?);
    }
    // Free buoys before lines, so that a line's fairlead can name one ("b1/buoy").
    for (i, b) in scene.buoy.iter().enumerate() {
        if let Some(p) = b.value.position {
            let name = m.name(&b.value.name, "buoy", i, b.line)?;
            m.append("buoy", i, b.line, aqua_mesh::buoy_node(&name, p))?;
        }
    }
    // Bodies before lines too: a fairlead can name a body's point ("barge/f1").
    for (i, b) in scene.body.iter().enumerate() {
        let name = m.name(&b.value.name, "body", i, b.line)?;
        let body = b
            .value
            .resolve()
            .map_err(|e| input(format!("{file}: line {}: [[body]] #{}: {e}", b.line, i + 1)))?;
        let hull = body.hull.map(|h| h.shape);
        m.append(
            "body",
            i,
            b.line,
            aqua_mesh::body_mesh(&name, body.centre, hull.as_ref(), &body.points),
        )?;
    }
    for (i, c) in scene.line.iter().enumerate() {
        add_line(scene, &mut m, i, c)?;
    }
    if m.mesh.nodes.is_empty() {
        return Err(input(format!(
            "{file}: the scene has no structure: add a [[cage]], [[panel]], [[line]], [[mesh]] \
             or [[farm]]"
        )));
    }
    Ok(MeshParts {
        mesh: m.mesh,
        nets: m.nets,
        farms,
    })
}

/// The seabed level z = −depth of a finite sea [m].
/// The strain by which hanging lines start stretched: [`aqua_mesh::INITIAL_STRETCH`] when a
/// static solve starts from the as-built shape (every element taut for its first tangent,
/// docs/theory/cages.md#single-line), 0 for dynamics-only runs, which start from the as-built
/// shape at rest.
fn start_stretch(scene: &Scene) -> f64 {
    match scene.analysis.kind {
        crate::scene::AnalysisKind::Dynamic => 0.0,
        _ => aqua_mesh::INITIAL_STRETCH,
    }
}

fn seabed_z(scene: &Scene) -> Option<f64> {
    scene.sea.depth.as_ref().and_then(|_| {
        scene
            .sea
            .constants()
            .ok()
            .and_then(|c| c.depth.finite())
            .map(|h| -h)
    })
}

/// Appends a `[[farm]]`: its cages, frame and anchor lines, each a uniquely named object.
fn add_farm(
    scene: &Scene,
    m: &mut Merge,
    i: usize,
    c: &crate::scene::Located<crate::scene::FarmSpec>,
) -> Result<BuiltFarm> {
    let mut p = c.value.params.clone();
    p.initial_stretch = start_stretch(scene);
    // Checked as every object name: it prefixes the farm's objects ("farm/cage_r1c1").
    let name = m.name(&p.name, "farm", i, c.line)?;
    p.name = Some(name.clone());
    let at = format!("{}: line {}: [[farm]] #{}", m.file, c.line, i + 1);
    let spec = &c.value;
    let (farm, buoy) = p
        .check_cage("cage", &spec.cage.params)
        .and_then(|_| {
            let buoy = farm_buoy(&name, spec.buoy.as_ref())?;
            p.build_slots(
                |r, col| spec.slot_cage(r, col).map(|s| s.params.clone()),
                seabed_z(scene),
            )
            .map(|farm| (farm, buoy))
        })
        .map_err(|e| SimError::at(at.clone(), e))?;
    for o in &farm.mesh.objects {
        m.claim(o.name.clone(), c.line)?;
    }
    // Each cage's own net keys (its slot's or [farm.cage]'s): the wake groups read them.
    for r in 1..=p.rows as usize {
        for col in 1..=p.columns as usize {
            if let Some(s) = spec.slot_cage(r, col) {
                m.nets
                    .insert(format!("{name}/cage_r{r}c{col}"), s.net_hydro.clone());
            }
        }
    }
    let counts = farm.counts(&name);
    let buoys = farm.buoys.clone();
    let node_off = m.mesh.append(farm.mesh);
    Ok(BuiltFarm {
        name,
        line: c.line,
        buoys: buoys.into_iter().map(|b| b + node_off).collect(),
        buoy,
        cages: farm.cages,
        anchors: farm.anchors,
        cage_wake: p.cage_wake.unwrap_or(true),
        counts,
    })
}

/// The `[farm.buoy]` of farm `obj`, checked; it is required.
fn farm_buoy(
    obj: &str,
    buoy: Option<&crate::buoy::BuoySpec>,
) -> std::result::Result<crate::buoy::Buoy, aqua_mesh::MeshError> {
    buoy.ok_or_else(|| {
        aqua_mesh::MeshError::param(
            obj,
            "buoy",
            "(missing)",
            "[farm.buoy] is required for every farm (one buoy per plate): a section table with \
             diameter, ea or youngs_modulus, mass_per_length or density",
        )
    })?
    .resolve_farm(obj)
}

/// Appends a `[[line]]`; a fairlead that names a node is welded to it.
fn add_line(
    scene: &Scene,
    m: &mut Merge,
    i: usize,
    c: &crate::scene::Located<crate::scene::LineSpec>,
) -> Result<()> {
    let file = m.file.clone();
    let seabed_z = seabed_z(scene);
    let mut p = c.value.params.clone();
    p.name = Some(m.name(&p.name, "line", i, c.line)?);
    p.initial_stretch = start_stretch(scene);
    let mut weld_to = None;
    let mut fair_pos = None;
    if let Some(Fairlead::Node(r)) = &p.fairlead {
        let nodes = resolve_ref(&m.mesh, r).ok_or_else(|| {
            input(format!(
                "{file}: line {}: [[line]] #{}: fairlead = \"{r}\" names no node (use \"object/group[k]\"); {}",
                c.line,
                i + 1,
                ref_hint(&m.mesh, r)
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
        let x = m.mesh.nodes[n];
        fair_pos = Some([x.x, x.y, x.z]);
        weld_to = Some(n);
    }
    m.append("line", i, c.line, p.build_with(fair_pos, seabed_z))?;
    if let Some(target) = weld_to {
        m.mesh.weld_tail(&[target]);
    }
    Ok(())
}
