//! ParaView output people can navigate: a time series of VTK multiblock files
//! (`<stem>.pvd` → `<stem>_NNNNNN.vtm` per step → one `.vtu` per block in `<stem>_NNNNNN/`).
//!
//! # Blocks
//!
//! Every object of the mesh (a cage, a panel, a line, an imported mesh; every copy of a
//! multi-origin object separately) is one top-level block, and holds up to three datasets named
//! after their kind:
//!
//! * `lines`: its line elements as `VTK_LINE` (twines, ropes, rings, chains), with the cell
//!   arrays of the caller's `line` arrays (tension, …);
//! * `panels`: its net panels as `VTK_TRIANGLE`/`VTK_QUAD` (screen-load elements: they carry no
//!   tension), with the caller's `panel` arrays;
//! * `points`: every node the object owns, once, as `VTK_VERTEX`; the point-data of all
//!   `points` datasets together is the point data of the whole model, node by node.
//!
//! A block is named after its object in the characters ParaView keeps in its hierarchy (ASCII
//! letters, digits and `_`; ParaView 5.11 silently drops every other character, so a block named
//! `farm/cage_r1c1` would be selected only as `/Root/farmcage_r1c1`): every other character of
//! the object's name becomes `_` (`farm/cage_r1c1` → `farm_cage_r1c1`, `m-east` → `m_east`),
//! copy k of a multi-origin object is `name_k` (the scene's `name#k`), a name starting with a
//! digit gets a leading `_` (as ParaView would), and a name that two objects would share gets
//! `_2`, `_3`, … on the later ones. [`NameTables::block_names`] lists the block paths and
//! [`NameTables::block_objects`] the object each one belongs to.
//!
//! So ParaView's *Multiblock Inspector* lists `cage0` → `lines`, `panels`, `points`, `m_east` →
//! `lines`, `points`, and each can be switched on and off by name; selectors are
//! `/Root/cage0/lines`, `/Root/farm_cage_r1c1`, `//panels`, …
//!
//! `lines` and `panels` datasets hold the nodes their cells use (a fairlead shared with a cage
//! appears in both objects' datasets); the `points` datasets partition the nodes. The node
//! index in the whole mesh is the point array `node_id`; the element/panel index is the cell
//! array `element_id`/`panel_id`.
//!
//! # Points
//!
//! Point coordinates are the positions passed to [`MultiblockSeries::write_step`] (for a run,
//! the deformed positions x = X + `displacement`). The undeformed geometry X is written once, by
//! [`MultiblockSeries::write_reference`], as `<stem>_reference.vtm` with the same blocks in the
//! same order and the same points. *Warp By Vector* (`displacement`, scale S − 1) applied to the
//! series gives X + S·`displacement` at every time step: the deformation scaled by S.
//!
//! # Field data (every dataset)
//!
//! `TimeValue` (the step time [s]) only: numbers, which every VTK reader (meshio included)
//! reads. The name tables — `object_names` (index = `object_id`), `group_names`
//! (`object/group`, index = `group_id`), `role_names` (index = `role_id`), `block_names`,
//! `block_objects` ([`NameTables`]) — are the caller's to write (`aqua run` puts them in
//! `run.json`); the block names themselves are in the `.vtm` hierarchy.
//!
//! # Files
//!
//! Per step: one directory, its block files written in place (each in one `write`), then the
//! `.vtm` written to a temporary name and renamed, then one line in the `.pvd`: the new
//! `<DataSet>` and the closing tags written in one `write` over the old closing tags, so a
//! long run never rewrites the `.pvd`. The parts of a block file that are the same every
//! step (ids, names, sections, connectivity) are rendered once. Data arrays are inline
//! base64 (`format="binary"`), so every file stays well-formed XML.
//!
//! Nothing is fsynced. What holds if the process stops at any moment (an error, Ctrl-C, a
//! kill): every step the `.pvd` lists is complete, and every `<stem>_NNNNNN.vtm` on disk is
//! complete and listed, except that a kill during the one small `.pvd` write can cut that
//! line. A failed step removes what it had written. Against an operating-system crash or a
//! power cut nothing is promised (the page cache may not have reached the disk).

use crate::error::{MeshError, Result};
use crate::model::{Mesh, PanelNodes, Role};
use base64::Engine;
use nalgebra::Point3;
use std::fmt::Write as _;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Values of a block array.
#[derive(Debug, Clone, PartialEq)]
pub enum ArrayValues {
    /// Floating-point values, `components` per entry, entry-major.
    F64 {
        /// Values per entry (1 scalar, 3 vector).
        components: usize,
        /// `components × count` values.
        values: Vec<f64>,
    },
    /// Integer flags or ids, one per entry.
    I32(Vec<i32>),
}

/// A named array given for every node, every line element or every panel of the whole mesh;
/// the writer hands each block its part.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockArray {
    /// Array name as shown in ParaView.
    pub name: String,
    /// The values.
    pub values: ArrayValues,
}

impl BlockArray {
    /// Scalar floating-point array.
    pub fn scalar(name: impl Into<String>, values: Vec<f64>) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::F64 {
                components: 1,
                values,
            },
        }
    }

    /// 3-vector array from `[x, y, z]` entries.
    pub fn vectors(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::F64 {
                components: 3,
                values: values.iter().flatten().copied().collect(),
            },
        }
    }

    /// Integer array (flags, ids).
    pub fn int(name: impl Into<String>, values: Vec<i32>) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::I32(values),
        }
    }

    fn components(&self) -> usize {
        match &self.values {
            ArrayValues::F64 { components, .. } => *components,
            ArrayValues::I32(_) => 1,
        }
    }

    fn len(&self) -> usize {
        match &self.values {
            ArrayValues::F64 { values, .. } => values.len(),
            ArrayValues::I32(v) => v.len(),
        }
    }
}

/// Caller arrays of one step: per node, per line element, per panel (whole-mesh order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepArrays {
    /// One entry per mesh node.
    pub point: Vec<BlockArray>,
    /// One entry per mesh line element.
    pub line: Vec<BlockArray>,
    /// One entry per mesh panel.
    pub panel: Vec<BlockArray>,
}

/// What a block dataset holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockKind {
    /// Line elements.
    Lines,
    /// Net panels.
    Panels,
    /// The object's nodes as vertices.
    Points,
}

impl BlockKind {
    /// `lines`, `panels` or `points`: the dataset's name under its object.
    pub fn as_str(self) -> &'static str {
        match self {
            BlockKind::Lines => "lines",
            BlockKind::Panels => "panels",
            BlockKind::Points => "points",
        }
    }
}

/// One dataset of the layout.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockSpec {
    /// The block's name: the object's name in the characters ParaView keeps (`cage0`,
    /// `farm_cage_r1c1`, `cage0_1` for copy 1 of a multi-origin object; see the module doc).
    pub object_label: String,
    /// Kind.
    pub kind: BlockKind,
    /// Object index.
    pub object: u32,
    /// Copy index.
    pub copy: u32,
    /// Mesh nodes of the dataset, in its local point order.
    pub nodes: Vec<usize>,
    /// Mesh line elements (lines) or panels (panels); empty for points.
    pub cells: Vec<usize>,
    /// File name inside the step directory.
    file: String,
}

impl BlockSpec {
    /// `cage0/lines`: the path of the dataset in the multiblock hierarchy.
    pub fn name(&self) -> String {
        format!("{}/{}", self.object_label, self.kind.as_str())
    }
}

/// How a mesh is split into blocks (the same for every step).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockLayout {
    /// Datasets, grouped by object in object order, kinds in the order lines, panels, points.
    pub blocks: Vec<BlockSpec>,
}

fn file_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// `name` in the characters ParaView keeps in a block hierarchy (ASCII letters, digits, `_`):
/// every other character becomes `_`, and a leading digit gets a `_` in front (see the module
/// doc).
pub fn paraview_block_name(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

impl BlockLayout {
    /// One object (per copy) at a time: its lines, its panels, its nodes. Kinds an object does
    /// not have are left out.
    pub fn new(mesh: &Mesh) -> Self {
        let mut units: Vec<(u32, u32)> = Vec::new();
        for (o, obj) in mesh.objects.iter().enumerate() {
            for c in 0..obj.origins.len().max(1) {
                units.push((o as u32, c as u32));
            }
        }
        // Every entity's (object, copy) must be a unit, even if a builder left `origins` empty.
        let mut extra: Vec<(u32, u32)> = mesh
            .node_owner
            .iter()
            .copied()
            .chain(mesh.lines.iter().map(|l| (l.object, l.copy)))
            .chain(mesh.panels.iter().map(|p| (p.object, p.copy)))
            .filter(|u| !units.contains(u))
            .collect();
        extra.sort_unstable();
        extra.dedup();
        units.extend(extra);
        units.sort_unstable();
        let copies = |o: u32| units.iter().filter(|u| u.0 == o).count();
        let mut blocks = Vec::new();
        let mut used_files: Vec<String> = Vec::new();
        for &(o, c) in &units {
            let name = mesh
                .objects
                .get(o as usize)
                .map_or_else(|| format!("object{o}"), |x| x.name.clone());
            let wanted = if copies(o) > 1 {
                paraview_block_name(&format!("{name}#{c}"))
            } else {
                paraview_block_name(&name)
            };
            let mut label = wanted.clone();
            let mut k = 2;
            while blocks.iter().any(|b: &BlockSpec| b.object_label == label) {
                label = format!("{wanted}_{k}");
                k += 1;
            }
            let lines: Vec<usize> = (0..mesh.lines.len())
                .filter(|&i| (mesh.lines[i].object, mesh.lines[i].copy) == (o, c))
                .collect();
            let panels: Vec<usize> = (0..mesh.panels.len())
                .filter(|&i| (mesh.panels[i].object, mesh.panels[i].copy) == (o, c))
                .collect();
            let owned: Vec<usize> = (0..mesh.nodes.len())
                .filter(|&n| mesh.node_owner.get(n) == Some(&(o, c)))
                .collect();
            let used_nodes = |elems: &mut dyn Iterator<Item = usize>| {
                let mut v: Vec<usize> = elems.collect();
                v.sort_unstable();
                v.dedup();
                v
            };
            let line_nodes = used_nodes(&mut lines.iter().flat_map(|&i| mesh.lines[i].nodes));
            let panel_nodes = used_nodes(
                &mut panels
                    .iter()
                    .flat_map(|&i| mesh.panels[i].nodes.as_slice().to_vec()),
            );
            for (kind, nodes, cells) in [
                (BlockKind::Lines, line_nodes, lines),
                (BlockKind::Panels, panel_nodes, panels),
                (BlockKind::Points, owned, Vec::new()),
            ] {
                let empty = match kind {
                    BlockKind::Points => nodes.is_empty(),
                    _ => cells.is_empty(),
                };
                if empty {
                    continue;
                }
                let mut file = format!("{}_{}.vtu", file_safe(&label), kind.as_str());
                if used_files.contains(&file) {
                    file = format!(
                        "{}_{}_{}.vtu",
                        file_safe(&label),
                        blocks.len(),
                        kind.as_str()
                    );
                }
                used_files.push(file.clone());
                blocks.push(BlockSpec {
                    object_label: label.clone(),
                    kind,
                    object: o,
                    copy: c,
                    nodes,
                    cells,
                    file,
                });
            }
        }
        BlockLayout { blocks }
    }
}

/// The name tables written as field data (and by callers into `run.json`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct NameTables {
    /// Object names, index = `object_id`.
    pub object_names: Vec<String>,
    /// `object/group`, index = `group_id`.
    pub group_names: Vec<String>,
    /// Role names, index = `role_id`.
    pub role_names: Vec<String>,
    /// Block paths (`cage0/lines`, `farm_cage_r1c1/panels`) in file order.
    pub block_names: Vec<String>,
    /// The object name of every entry of `block_names` (`farm/cage_r1c1`; a copy of a
    /// multi-origin object as `name#k`).
    pub block_objects: Vec<String>,
}

impl NameTables {
    /// The tables of `mesh` split by `layout`.
    pub fn new(mesh: &Mesh, layout: &BlockLayout) -> Self {
        NameTables {
            object_names: mesh.objects.iter().map(|o| o.name.clone()).collect(),
            group_names: mesh
                .groups
                .iter()
                .map(|g| {
                    let o = mesh
                        .objects
                        .get(g.object as usize)
                        .map_or("?", |o| o.name.as_str());
                    format!("{o}/{}", g.name)
                })
                .collect(),
            role_names: Role::ALL
                .iter()
                .map(|r| {
                    serde_json::to_value(r)
                        .ok()
                        .and_then(|v| v.as_str().map(str::to_string))
                        .unwrap_or_else(|| r.default_name().to_string())
                })
                .collect(),
            block_names: layout.blocks.iter().map(BlockSpec::name).collect(),
            block_objects: layout
                .blocks
                .iter()
                .map(|b| {
                    let name = mesh
                        .objects
                        .get(b.object as usize)
                        .map_or_else(|| format!("object{}", b.object), |o| o.name.clone());
                    let copies = layout
                        .blocks
                        .iter()
                        .filter(|x| x.object == b.object && x.copy != b.copy)
                        .count();
                    if copies > 0 {
                        format!("{name}#{}", b.copy)
                    } else {
                        name
                    }
                })
                .collect(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// XML writing

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Inline binary data: base64 of the byte count (UInt64) followed by the bytes, appended to
/// `out`.
fn b64_into(out: &mut String, bytes: &[u8]) {
    let mut buf = Vec::with_capacity(8 + bytes.len());
    buf.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    buf.extend_from_slice(bytes);
    base64::engine::general_purpose::STANDARD.encode_string(buf, out);
}

fn data_array(out: &mut String, ty: &str, name: &str, comps: usize, bytes: &[u8]) {
    let _ = write!(
        out,
        "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{comps}\" \
         format=\"binary\">\n          ",
        xml_escape(name),
    );
    b64_into(out, bytes);
    out.push_str("\n        </DataArray>\n");
}

fn f64_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn i32_bytes(v: &[i32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn i64_bytes(v: &[i64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn array_subset(out: &mut String, a: &BlockArray, idx: &[usize]) {
    match &a.values {
        ArrayValues::F64 { components, values } => {
            let k = *components;
            let sub: Vec<f64> = idx
                .iter()
                .flat_map(|&i| values[k * i..k * (i + 1)].iter().copied())
                .collect();
            data_array(out, "Float64", &a.name, k, &f64_bytes(&sub));
        }
        ArrayValues::I32(v) => {
            let sub: Vec<i32> = idx.iter().map(|&i| v[i]).collect();
            data_array(out, "Int32", &a.name, 1, &i32_bytes(&sub));
        }
    }
}

/// Write `path` by filling a temporary file next to it and renaming it into place (no fsync:
/// atomic against the process stopping, not against a power cut).
fn write_replace(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let fname = path
        .file_name()
        .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
    let tmp = dir.join(format!(".{fname}.tmp{}", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|_| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

fn check_arrays(arrays: &[BlockArray], n: usize, location: &'static str) -> Result<()> {
    for (k, a) in arrays.iter().enumerate() {
        let err = |m: String| MeshError::VtkArray {
            location,
            name: a.name.clone(),
            message: m,
        };
        if a.name.is_empty() || a.name.contains(['"', '<', '>', '&']) {
            return Err(err("name must be non-empty without \" < > &".into()));
        }
        if BUILTIN.contains(&a.name.as_str()) || arrays[..k].iter().any(|b| b.name == a.name) {
            return Err(err(format!(
                "name is already used (built-in: {})",
                BUILTIN.join(", ")
            )));
        }
        let want = a.components() * n;
        if a.components() == 0 || a.len() != want {
            return Err(err(format!(
                "has {} values; expected {} components × {n} = {want}",
                a.len(),
                a.components()
            )));
        }
        if let ArrayValues::F64 { values, components } = &a.values
            && let Some(i) = values.iter().position(|v| !v.is_finite())
        {
            return Err(err(format!(
                "value {} (entry {}) is not finite",
                values[i],
                i / components
            )));
        }
    }
    Ok(())
}

/// Array names the writer sets itself.
pub const BUILTIN: [&str; 16] = [
    "node_id",
    "object_id",
    "copy_id",
    "fixed",
    "point_weight",
    "element_id",
    "panel_id",
    "group_id",
    "role_id",
    "diameter",
    "elastic_diameter",
    "hydro_diameter",
    "twine_diameter",
    "solidity",
    "TimeValue",
    "block_name",
];

/// Per-mesh data computed once: fixed flags and point weights per node.
#[derive(Debug, Clone, PartialEq)]
struct NodeData {
    fixed: Vec<i32>,
    weight: Vec<f64>,
}

/// The parts of a block's `.vtu` that are the same every step (ids, names, sections,
/// connectivity), rendered once; [`BlockTemplate::render`] puts a step's time, arrays and
/// points between them.
#[derive(Debug, Clone, PartialEq)]
struct BlockTemplate {
    /// Up to the field data's first array; the field data after `TimeValue` up to the
    /// built-in point arrays; the built-in cell arrays; the opening of `<Points>`; the cells
    /// and closing tags.
    parts: [String; 5],
}

impl BlockTemplate {
    fn new(mesh: &Mesh, spec: &BlockSpec, nd: &NodeData) -> Self {
        let mut local = std::collections::HashMap::with_capacity(spec.nodes.len());
        for (k, &n) in spec.nodes.iter().enumerate() {
            local.insert(n, k as i64);
        }
        let mut conn: Vec<i64> = Vec::new();
        let mut offsets: Vec<i64> = Vec::new();
        let mut types: Vec<u8> = Vec::new();
        match spec.kind {
            BlockKind::Lines => {
                for &e in &spec.cells {
                    conn.extend(mesh.lines[e].nodes.iter().map(|n| local[n]));
                    offsets.push(conn.len() as i64);
                    types.push(3);
                }
            }
            BlockKind::Panels => {
                for &p in &spec.cells {
                    let pn = &mesh.panels[p].nodes;
                    conn.extend(pn.as_slice().iter().map(|n| local[n]));
                    offsets.push(conn.len() as i64);
                    types.push(match pn {
                        PanelNodes::Tri(_) => 5,
                        PanelNodes::Quad(_) => 9,
                    });
                }
            }
            BlockKind::Points => {
                for k in 0..spec.nodes.len() {
                    conn.push(k as i64);
                    offsets.push(k as i64 + 1);
                    types.push(1);
                }
            }
        }
        let mut parts: [String; 5] = Default::default();
        let mut s = String::new();
        s.push_str(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    \
         <FieldData>\n",
        );
        parts[0] = std::mem::take(&mut s);
        let _ = writeln!(
            s,
            "    </FieldData>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            spec.nodes.len(),
            types.len()
        );
        // Point data.
        s.push_str("      <PointData>\n");
        let nodes = &spec.nodes;
        let ids: Vec<i32> = nodes.iter().map(|&n| n as i32).collect();
        data_array(&mut s, "Int32", "node_id", 1, &i32_bytes(&ids));
        let own: Vec<i32> = nodes.iter().map(|&n| mesh.node_owner[n].0 as i32).collect();
        data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&own));
        let cp: Vec<i32> = nodes.iter().map(|&n| mesh.node_owner[n].1 as i32).collect();
        data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
        let fx: Vec<i32> = nodes.iter().map(|&n| nd.fixed[n]).collect();
        data_array(&mut s, "Int32", "fixed", 1, &i32_bytes(&fx));
        let w: Vec<f64> = nodes.iter().map(|&n| nd.weight[n]).collect();
        data_array(&mut s, "Float64", "point_weight", 1, &f64_bytes(&w));
        parts[1] = std::mem::take(&mut s);
        s.push_str("      </PointData>\n      <CellData>\n");
        // Cell data.
        match spec.kind {
            BlockKind::Lines => {
                let c = &spec.cells;
                let ids: Vec<i32> = c.iter().map(|&e| e as i32).collect();
                data_array(&mut s, "Int32", "element_id", 1, &i32_bytes(&ids));
                let lines = || c.iter().map(|&e| &mesh.lines[e]);
                let g: Vec<i32> = lines().map(|l| l.group as i32).collect();
                data_array(&mut s, "Int32", "group_id", 1, &i32_bytes(&g));
                let r: Vec<i32> = lines()
                    .map(|l| mesh.groups[l.group].role.id() as i32)
                    .collect();
                data_array(&mut s, "Int32", "role_id", 1, &i32_bytes(&r));
                let o: Vec<i32> = lines().map(|l| l.object as i32).collect();
                data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&o));
                let cp: Vec<i32> = lines().map(|l| l.copy as i32).collect();
                data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
                // The element's own diameters: its section scale k multiplies areas.
                type Diam = fn(&crate::Section, f64) -> f64;
                let diam: [(&str, Diam); 3] = [
                    ("diameter", |s, k| s.diameter * k.sqrt()),
                    ("elastic_diameter", |s, k| s.elastic_diameter * k.sqrt()),
                    ("hydro_diameter", |s, k| s.hydro_diameter * k),
                ];
                for (name, f) in diam {
                    let d: Vec<f64> = lines()
                        .map(|l| {
                            mesh.groups[l.group]
                                .section
                                .as_ref()
                                .map_or(0.0, |s| f(s, l.section_scale))
                        })
                        .collect();
                    data_array(&mut s, "Float64", name, 1, &f64_bytes(&d));
                }
            }
            BlockKind::Panels => {
                let c = &spec.cells;
                let ids: Vec<i32> = c.iter().map(|&e| e as i32).collect();
                data_array(&mut s, "Int32", "panel_id", 1, &i32_bytes(&ids));
                let panels = || c.iter().map(|&e| &mesh.panels[e]);
                let g: Vec<i32> = panels().map(|p| p.group as i32).collect();
                data_array(&mut s, "Int32", "group_id", 1, &i32_bytes(&g));
                let r: Vec<i32> = panels()
                    .map(|p| mesh.groups[p.group].role.id() as i32)
                    .collect();
                data_array(&mut s, "Int32", "role_id", 1, &i32_bytes(&r));
                let o: Vec<i32> = panels().map(|p| p.object as i32).collect();
                data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&o));
                let cp: Vec<i32> = panels().map(|p| p.copy as i32).collect();
                data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
                let net = |p: &crate::Panel| {
                    mesh.objects
                        .get(p.object as usize)
                        .and_then(|o| o.net.as_ref())
                };
                let dw: Vec<f64> = panels()
                    .map(|p| net(p).map_or(0.0, |n| n.twine_diameter))
                    .collect();
                data_array(&mut s, "Float64", "twine_diameter", 1, &f64_bytes(&dw));
                let sn: Vec<f64> = panels()
                    .map(|p| net(p).map_or(0.0, |n| n.solidity))
                    .collect();
                data_array(&mut s, "Float64", "solidity", 1, &f64_bytes(&sn));
            }
            BlockKind::Points => {}
        }
        parts[2] = std::mem::take(&mut s);
        s.push_str("      </CellData>\n      <Points>\n");
        parts[3] = std::mem::take(&mut s);
        s.push_str("      </Points>\n      <Cells>\n");
        data_array(&mut s, "Int64", "connectivity", 1, &i64_bytes(&conn));
        data_array(&mut s, "Int64", "offsets", 1, &i64_bytes(&offsets));
        data_array(&mut s, "UInt8", "types", 1, &types);
        s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
        parts[4] = s;
        BlockTemplate { parts }
    }

    /// The block's `.vtu` at `time` (none: the reference) with the caller's arrays.
    fn render(
        &self,
        spec: &BlockSpec,
        positions: &[Point3<f64>],
        time: Option<f64>,
        arrays: &StepArrays,
    ) -> String {
        let p = &self.parts;
        let n = spec.nodes.len();
        let per_point: usize = arrays
            .point
            .iter()
            .map(|a| 8 * a.components())
            .sum::<usize>()
            + 24;
        let per_cell: usize = 8 * (arrays.line.len() + arrays.panel.len());
        let cap = p.iter().map(String::len).sum::<usize>()
            + (n * per_point + spec.cells.len() * per_cell) * 4 / 3
            + 512 * (arrays.point.len() + arrays.line.len() + arrays.panel.len() + 2);
        let mut s = String::with_capacity(cap);
        s.push_str(&p[0]);
        if let Some(t) = time {
            s.push_str(
                "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
                 format=\"binary\">\n        ",
            );
            b64_into(&mut s, &t.to_le_bytes());
            s.push_str("\n      </DataArray>\n");
        }
        s.push_str(&p[1]);
        for a in &arrays.point {
            array_subset(&mut s, a, &spec.nodes);
        }
        s.push_str(&p[2]);
        let cell_arrays = match spec.kind {
            BlockKind::Lines => arrays.line.as_slice(),
            BlockKind::Panels => arrays.panel.as_slice(),
            BlockKind::Points => &[],
        };
        for a in cell_arrays {
            array_subset(&mut s, a, &spec.cells);
        }
        s.push_str(&p[3]);
        let pts: Vec<f64> = spec
            .nodes
            .iter()
            .flat_map(|&n| {
                let p = positions[n];
                [p.x, p.y, p.z]
            })
            .collect();
        data_array(&mut s, "Float64", "Points", 3, &f64_bytes(&pts));
        s.push_str(&p[4]);
        s
    }
}

fn vtm_text(layout: &BlockLayout, subdir: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n",
    );
    let mut i = 0;
    let mut top = 0;
    while i < layout.blocks.len() {
        let label = &layout.blocks[i].object_label;
        let (o, c) = (layout.blocks[i].object, layout.blocks[i].copy);
        let _ = writeln!(
            s,
            "    <Block index=\"{top}\" name=\"{}\">",
            xml_escape(label)
        );
        let mut k = 0;
        while i < layout.blocks.len() && (layout.blocks[i].object, layout.blocks[i].copy) == (o, c)
        {
            let b = &layout.blocks[i];
            let _ = writeln!(
                s,
                "      <DataSet index=\"{k}\" name=\"{}\" file=\"{}/{}\"/>",
                b.kind.as_str(),
                xml_escape(subdir),
                xml_escape(&b.file)
            );
            i += 1;
            k += 1;
        }
        s.push_str("    </Block>\n");
        top += 1;
    }
    s.push_str("  </vtkMultiBlockDataSet>\n</VTKFile>\n");
    s
}

/// A `.pvd` collection that grows by one `<DataSet>` line per step, written in place.
#[derive(Debug)]
struct GrowingPvd {
    path: PathBuf,
    entries: Vec<(f64, String)>,
    /// Open file and the byte offset of its closing tags.
    file: Option<(std::fs::File, u64)>,
}

const PVD_HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
                        byte_order=\"LittleEndian\">\n  <Collection>\n";
const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

fn pvd_line(t: f64, f: &str) -> String {
    format!(
        "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
        xml_escape(f)
    )
}

impl GrowingPvd {
    fn rewrite(&mut self) -> Result<()> {
        let mut s = String::from(PVD_HEAD);
        for (t, f) in &self.entries {
            s.push_str(&pvd_line(*t, f));
        }
        let body = s.len() as u64;
        s.push_str(PVD_TAIL);
        write_replace(&self.path, s.as_bytes())?;
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.path)
            .map_err(|source| MeshError::Io {
                path: self.path.clone(),
                source,
            })?;
        self.file = Some((f, body));
        Ok(())
    }

    fn add(&mut self, t: f64, file: String) -> Result<()> {
        let line = pvd_line(t, &file);
        self.entries.push((t, file));
        let Some((f, body)) = self.file.as_mut() else {
            return self.rewrite();
        };
        // One write of the new line and the closing tags over the old closing tags.
        let text = format!("{line}{PVD_TAIL}");
        let r = f
            .seek(SeekFrom::Start(*body))
            .and_then(|_| f.write_all(text.as_bytes()));
        match r {
            Ok(()) => {
                *body += line.len() as u64;
                Ok(())
            }
            Err(_) => self.rewrite(),
        }
    }
}

/// A multiblock time series `<stem>.pvd` + `<stem>_NNNNNN.vtm` (+ blocks in `<stem>_NNNNNN/`).
#[derive(Debug)]
pub struct MultiblockSeries {
    dir: PathBuf,
    stem: String,
    layout: BlockLayout,
    names: NameTables,
    /// The fixed part of every block's file, in layout order.
    templates: Vec<BlockTemplate>,
    pvd: GrowingPvd,
    step: usize,
}

impl MultiblockSeries {
    /// A new series of `mesh` in `dir` (created if needed). Nothing is written yet; files of an
    /// earlier series with the same stem (`<stem>_NNNNNN.vtm` and their directories) are
    /// removed so that the directory holds only what the new `.pvd` lists.
    pub fn new(dir: impl Into<PathBuf>, stem: &str, mesh: &Mesh) -> Result<Self> {
        let dir = dir.into();
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| MeshError::Io { path, source }
        };
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        let prefix = format!("{stem}_");
        if let Ok(entries) = std::fs::read_dir(&dir) {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                let Some(rest) = name.strip_prefix(&prefix) else {
                    continue;
                };
                let digits = rest.strip_suffix(".vtm").or(rest.strip_suffix(".vtu"));
                let is_step = |s: &str| s.len() == 6 && s.bytes().all(|b| b.is_ascii_digit());
                if digits.is_some_and(is_step) {
                    let _ = std::fs::remove_file(e.path());
                } else if is_step(rest) && e.path().is_dir() {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        let layout = BlockLayout::new(mesh);
        let names = NameTables::new(mesh, &layout);
        let templates = templates(mesh, &layout);
        let pvd_path = dir.join(format!("{stem}.pvd"));
        // A `.pvd` left by an earlier run lists files that were just removed.
        let _ = std::fs::remove_file(&pvd_path);
        Ok(MultiblockSeries {
            pvd: GrowingPvd {
                path: pvd_path,
                entries: Vec::new(),
                file: None,
            },
            dir,
            stem: stem.to_string(),
            layout,
            names,
            templates,
            step: 0,
        })
    }

    /// The block layout.
    pub fn layout(&self) -> &BlockLayout {
        &self.layout
    }

    /// The name tables.
    pub fn names(&self) -> &NameTables {
        &self.names
    }

    /// Path of the `.pvd`.
    pub fn pvd_path(&self) -> &Path {
        &self.pvd.path
    }

    /// `(time, .vtm file relative to the .pvd)` of the steps written.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.pvd.entries
    }

    fn check(&self, mesh: &Mesh, positions: &[Point3<f64>], arrays: &StepArrays) -> Result<()> {
        if positions.len() != mesh.nodes.len() {
            return Err(MeshError::VtkArray {
                location: "point",
                name: "positions".into(),
                message: format!(
                    "{} positions for {} nodes",
                    positions.len(),
                    mesh.nodes.len()
                ),
            });
        }
        if let Some(i) = positions
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(MeshError::VtkArray {
                location: "point",
                name: "positions".into(),
                message: format!("node {i} has a non-finite coordinate"),
            });
        }
        check_arrays(&arrays.point, mesh.nodes.len(), "point")?;
        check_arrays(&arrays.line, mesh.lines.len(), "line cell")?;
        check_arrays(&arrays.panel, mesh.panels.len(), "panel cell")
    }

    /// Writes the undeformed geometry once as `<stem>_reference.vtm` (+ `<stem>_reference/`),
    /// same blocks and points as every step, built-in arrays only. Returns the `.vtm` path.
    pub fn write_reference(&self, mesh: &Mesh) -> Result<PathBuf> {
        let empty = StepArrays::default();
        let name = format!("{}_reference", self.stem);
        write_vtm(
            &self.dir,
            &name,
            &self.layout,
            &self.templates,
            &mesh.nodes,
            None,
            &empty,
        )
    }

    /// Writes one step at `time` [s] (after the previous step) and lists it in the `.pvd`.
    /// `mesh` is the mesh the series was made for (its block files' fixed parts were rendered
    /// from it). Returns the `.vtm` path.
    pub fn write_step(
        &mut self,
        time: f64,
        mesh: &Mesh,
        positions: &[Point3<f64>],
        arrays: &StepArrays,
    ) -> Result<PathBuf> {
        let bad = |m: String| MeshError::VtkArray {
            location: "pvd",
            name: "time".into(),
            message: m,
        };
        if !time.is_finite() {
            return Err(bad(format!("time {time} is not finite")));
        }
        if let Some(&(last, _)) = self.pvd.entries.last()
            && time <= last
        {
            return Err(bad(format!(
                "time {time} s is not after the previous step {last} s"
            )));
        }
        self.check(mesh, positions, arrays)?;
        let name = format!("{}_{:06}", self.stem, self.step);
        let vtm = write_vtm(
            &self.dir,
            &name,
            &self.layout,
            &self.templates,
            positions,
            Some(time),
            arrays,
        )?;
        self.pvd.add(time, format!("{name}.vtm"))?;
        self.step += 1;
        Ok(vtm)
    }
}

/// The fixed part of every block's file of `layout`, in layout order.
fn templates(mesh: &Mesh, layout: &BlockLayout) -> Vec<BlockTemplate> {
    let mut fixed = vec![0i32; mesh.nodes.len()];
    for i in mesh.fixed_nodes() {
        fixed[i] = 1;
    }
    let mut weight = vec![0.0; mesh.nodes.len()];
    for w in &mesh.weights {
        weight[w.node] += w.weight;
    }
    let nodes = NodeData { fixed, weight };
    layout
        .blocks
        .iter()
        .map(|b| BlockTemplate::new(mesh, b, &nodes))
        .collect()
}

/// Writes the blocks into `<dir>/<name>/`, then `<dir>/<name>.vtm` (temporary name + rename: a
/// `.vtm` under its final name is always complete). On an error, what was written is removed
/// again. Returns the `.vtm` path.
fn write_vtm(
    dir: &Path,
    name: &str,
    layout: &BlockLayout,
    templates: &[BlockTemplate],
    positions: &[Point3<f64>],
    time: Option<f64>,
    arrays: &StepArrays,
) -> Result<PathBuf> {
    let sub = dir.join(name);
    let vtm = dir.join(format!("{name}.vtm"));
    let result = (|| {
        std::fs::create_dir_all(&sub).map_err(|source| MeshError::Io {
            path: sub.clone(),
            source,
        })?;
        for (b, tpl) in layout.blocks.iter().zip(templates) {
            // Written in place: the block is reachable only through the `.vtm`, which is
            // written after it.
            let path = sub.join(&b.file);
            let text = tpl.render(b, positions, time, arrays);
            std::fs::write(&path, text).map_err(|source| MeshError::Io { path, source })?;
        }
        write_replace(&vtm, vtm_text(layout, name).as_bytes())
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&vtm);
        let _ = std::fs::remove_dir_all(&sub);
        return Err(e);
    }
    Ok(vtm)
}

/// Writes the undeformed geometry of `mesh` as the multiblock file `path` (`<stem>.vtm`) with
/// its block files in `<stem>/` next to it: the blocks, points and built-in arrays of a run's
/// `<stem>_reference.vtm` ([`MultiblockSeries::write_reference`]), without a time. The
/// directory `<stem>/` is replaced. Returns the `.vtm` path.
pub fn write_geometry(path: &Path, mesh: &Mesh) -> Result<PathBuf> {
    let bad = |path: &Path, m: &str| MeshError::VtkPath {
        path: path.to_path_buf(),
        message: m.to_string(),
    };
    if path.extension().and_then(|e| e.to_str()) != Some("vtm") {
        return Err(bad(path, "a multiblock file name must end in .vtm"));
    }
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| bad(path, "the file name needs a UTF-8 stem before .vtm"))?;
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|source| MeshError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    // The block directory is cleared, which is only safe if it holds nothing but block files.
    let sub = dir.join(name);
    if sub.exists() {
        let foreign = std::fs::read_dir(&sub)
            .map_err(|source| MeshError::Io {
                path: sub.clone(),
                source,
            })?
            .flatten()
            .any(|e| {
                !(e.path().is_file()
                    && e.path().extension().and_then(|x| x.to_str()) == Some("vtu"))
            });
        if foreign {
            return Err(bad(
                &sub,
                "the block directory exists and holds files other than .vtu; \
                 choose another .vtm name or remove the directory",
            ));
        }
        std::fs::remove_dir_all(&sub).map_err(|source| MeshError::Io {
            path: sub.clone(),
            source,
        })?;
    }
    let layout = BlockLayout::new(mesh);
    let templates = templates(mesh, &layout);
    write_vtm(
        dir,
        name,
        &layout,
        &templates,
        &mesh.nodes,
        None,
        &StepArrays::default(),
    )
}
