//! How a mesh is split into blocks (one per object and copy, with `lines`, `panels` and
//! `points` datasets), the block names ParaView keeps, and the name tables.

use crate::model::Mesh;
use crate::model::Role;

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
    pub(super) file: String,
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

pub(super) fn file_safe(s: &str) -> String {
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
