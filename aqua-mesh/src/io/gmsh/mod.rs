//! gmsh import (`[[mesh]]`, docs/theory/cages.md#gmsh-import).
//!
//! Physical group names (after `rename`) map to roles: `net`/`net_panels` (dim 2, screen
//! panels), `twines`/`net_twines` (dim 1), `ropes`, `tie_lines`, `top_ring`, `top_links`,
//! `bottom_ring` (dim 1), `line:<name>` (dim 1), `fixed`, `sinkers`, `tip`, `anchor`,
//! `fairlead`, `net_top`, `nodes:<name>` (dim 0–2). Nodes are renumbered densely in file order;
//! nodes used by no kept element are dropped.

mod check41;
mod reader;

pub use reader::{
    PhysicalName, RawElement, RawMsh, RawNode, element_type_name, parse_msh, read_msh,
};

use crate::cage::default_frame_section;
use crate::error::{FilePos, MeshError, Result};
use crate::mesh_builder::{MeshBuilder, replicate};
use crate::model::{Mesh, NetElement, Object, ObjectKind, PanelNodes, Role};
use crate::net::NetParams;
use crate::net_triangle::{TwineFrame, make_net_triangles};
use crate::section::Section;
use crate::section_override::SectionOverride;
use nalgebra::{Point3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// One `[[mesh]]` table.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GmshParams {
    /// `name` (default `mesh0`).
    pub name: Option<String>,
    /// `file`: path of the `.msh` file (relative paths are resolved by the caller).
    pub file: PathBuf,
    /// `scale` applied first, > 0, default 1.
    pub scale: Option<f64>,
    /// `rotate_deg` [rx, ry, rz] [degrees], applied about x, then y, then z, after scaling.
    pub rotate_deg: Option<[f64; 3]>,
    /// `translate` [m], applied after the rotation.
    pub translate: Option<[f64; 3]>,
    /// `origins`: copies, each translated by its origin (default `[[0, 0, 0]]`).
    pub origins: Option<Vec<[f64; 3]>>,
    /// `rename = { "GmshName" = "role" }`.
    #[serde(default)]
    pub rename: BTreeMap<String, String>,
    /// `net.*`.
    #[serde(default)]
    pub net: NetParams,
    /// `groups.<group>` section overrides of line groups.
    #[serde(default)]
    pub groups: BTreeMap<String, SectionOverride>,
}

/// What a physical group becomes.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Target {
    Panels,
    Lines(String, Role),
    Nodes(String, Role),
}

/// The valid physical names, for messages.
pub const VALID_NAMES: &str = "net (alias net_panels; dim 2), twines (alias net_twines; dim 1), \
ropes, tie_lines, top_ring, top_links, bottom_ring, line:<name> (dim 1), fixed, sinkers, tip, \
anchor, fairlead, net_top, nodes:<name> (dim 0-2)";

/// Why a physical name has no role.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum RoleError {
    /// A role's name on a group of another dimension.
    #[error("physical group `{name}` has dimension {dim}, but role `{name}` needs {need}")]
    Dimension {
        name: String,
        dim: i32,
        need: &'static str,
    },
    /// A name that is no role.
    #[error("unknown physical group name `{0}`")]
    Unknown(String),
}

/// Role of a physical name of dimension `dim`; an error if unknown or the wrong dimension.
fn classify(name: &str, dim: i32) -> std::result::Result<Target, RoleError> {
    let need = |ok: bool, need: &'static str, t: Target| {
        if ok {
            Ok(t)
        } else {
            Err(RoleError::Dimension {
                name: name.to_string(),
                dim,
                need,
            })
        }
    };
    let line_roles = [
        ("ropes", Role::Ropes),
        ("tie_lines", Role::TieLines),
        ("top_ring", Role::TopRing),
        ("top_links", Role::TopLinks),
        ("bottom_ring", Role::BottomRing),
    ];
    let node_roles = [
        ("fixed", Role::Fixed),
        ("sinkers", Role::Sinkers),
        ("tip", Role::Tip),
        ("anchor", Role::Anchor),
        ("fairlead", Role::Fairlead),
        ("net_top", Role::NetTop),
    ];
    match name {
        "net" | "net_panels" => need(dim == 2, "dimension 2 (surfaces)", Target::Panels),
        "twines" | "net_twines" => need(
            dim == 1,
            "dimension 1 (curves)",
            Target::Lines("net_twines".into(), Role::NetTwines),
        ),
        _ => {
            if let Some(&(n, r)) = line_roles.iter().find(|(n, _)| *n == name) {
                return need(dim == 1, "dimension 1 (curves)", Target::Lines(n.into(), r));
            }
            if let Some(&(n, r)) = node_roles.iter().find(|(n, _)| *n == name) {
                return need(
                    (0..=2).contains(&dim),
                    "dimension 0, 1 or 2",
                    Target::Nodes(n.into(), r),
                );
            }
            if let Some(u) = name.strip_prefix("line:").filter(|u| !u.is_empty()) {
                return need(
                    dim == 1,
                    "dimension 1 (curves)",
                    Target::Lines(u.into(), Role::UserLines),
                );
            }
            if let Some(u) = name.strip_prefix("nodes:").filter(|u| !u.is_empty()) {
                return need(
                    (0..=2).contains(&dim),
                    "dimension 0, 1 or 2",
                    Target::Nodes(u.into(), Role::UserNodes),
                );
            }
            Err(RoleError::Unknown(name.to_string()))
        }
    }
}

fn gerr(file: &Path, position: FilePos, message: impl Into<String>) -> MeshError {
    MeshError::Gmsh {
        file: file.to_path_buf(),
        position,
        message: message.into(),
    }
}

/// Read `params.file` and build the mesh.
pub fn import_gmsh(params: &GmshParams) -> Result<Mesh> {
    let raw = read_msh(&params.file)?;
    import_raw(params, &raw)
}

/// Build a mesh from an already parsed file.
pub fn import_raw(params: &GmshParams, raw: &RawMsh) -> Result<Mesh> {
    let name = params.name.clone().unwrap_or_else(|| "mesh0".into());
    let obj = name.as_str();
    let file = params.file.as_path();
    let mut notices = Vec::new();

    // Transform (scale, rotate x→y→z, translate).
    let scale = params.scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(MeshError::param(
            obj,
            "scale",
            scale,
            "must be a finite number > 0",
        ));
    }
    let rot = params.rotate_deg.unwrap_or([0.0; 3]);
    let tr = params.translate.unwrap_or([0.0; 3]);
    for (k, v) in [("rotate_deg", rot), ("translate", tr)] {
        if v.iter().any(|c| !c.is_finite()) {
            return Err(MeshError::param(obj, k, format!("{v:?}"), "must be finite"));
        }
    }
    let origins = params.origins.clone().unwrap_or_else(|| vec![[0.0; 3]]);
    if origins.is_empty() {
        return Err(MeshError::param(
            obj,
            "origins",
            "[]",
            "needs at least one point",
        ));
    }
    if origins.iter().flatten().any(|c| !c.is_finite()) {
        return Err(MeshError::param(
            obj,
            "origins",
            format!("{origins:?}"),
            "must be finite",
        ));
    }
    let r = Rotation3::from_axis_angle(&Vector3::z_axis(), rot[2].to_radians())
        * Rotation3::from_axis_angle(&Vector3::y_axis(), rot[1].to_radians())
        * Rotation3::from_axis_angle(&Vector3::x_axis(), rot[0].to_radians());
    let shift = Vector3::from(tr) + Vector3::from(origins[0]);

    // Physical names → targets (after rename). Every name that is not understood is reported
    // at once.
    let mut targets: HashMap<(i32, i32), Target> = HashMap::new();
    let mut bad: Vec<(FilePos, String)> = Vec::new();
    for pn in &raw.names {
        let mapped = params.rename.get(&pn.name).unwrap_or(&pn.name);
        match classify(mapped, pn.dim) {
            Ok(t) => {
                targets.insert((pn.dim, pn.tag), t);
            }
            Err(reason) => {
                let renamed = if mapped != &pn.name {
                    format!(" (renamed from `{}`)", pn.name)
                } else {
                    String::new()
                };
                bad.push((pn.pos, format!("{reason}{renamed} ({})", pn.pos)));
            }
        }
    }
    if let Some((pos, _)) = bad.first() {
        let list: Vec<&str> = bad.iter().map(|(_, m)| m.as_str()).collect();
        let example = raw
            .names
            .iter()
            .find(|n| classify(params.rename.get(&n.name).unwrap_or(&n.name), n.dim).is_err())
            .map_or("<name>", |n| n.name.as_str());
        return Err(gerr(
            file,
            *pos,
            format!(
                "{} physical group name{} not understood: {}; valid names: {VALID_NAMES}. \
                 Rename the groups in gmsh or map them with `rename = {{ \"{example}\" = \
                 \"<role>\" }}`",
                bad.len(),
                if bad.len() == 1 { " is" } else { "s are" },
                list.join("; ")
            ),
        ));
    }
    for k in params.rename.keys() {
        if !raw.names.iter().any(|n| &n.name == k) {
            let found: Vec<&str> = raw.names.iter().map(|n| n.name.as_str()).collect();
            return Err(MeshError::param(
                obj,
                &format!("rename.{k}"),
                k,
                format!(
                    "the file has no physical group of that name; its groups: {}",
                    if found.is_empty() {
                        "(none)".into()
                    } else {
                        found.join(", ")
                    }
                ),
            ));
        }
    }

    // Node tag → raw index.
    let mut by_tag: HashMap<u64, usize> = HashMap::with_capacity(raw.nodes.len());
    for (i, n) in raw.nodes.iter().enumerate() {
        if n.x.iter().any(|c| !c.is_finite()) {
            return Err(gerr(
                file,
                FilePos::File,
                format!("node {} has a non-finite coordinate", n.tag),
            ));
        }
        by_tag.insert(n.tag, i);
    }

    // Classify elements.
    struct Kept<'a> {
        el: &'a RawElement,
        element_target: Option<Target>,
        node_targets: Vec<Target>,
    }
    let mut kept = Vec::new();
    let mut ignored = 0usize;
    for el in &raw.elements {
        if el.physical.is_empty() {
            ignored += 1;
            continue;
        }
        let mut element_target = None;
        let mut node_targets = Vec::new();
        for &p in &el.physical {
            let t = targets.get(&(el.dim, p)).ok_or_else(|| {
                gerr(
                    file,
                    el.pos,
                    format!(
                        "element {} belongs to physical group {p} (dimension {}), which has no \
                         name; give every physical group a name; valid names: {VALID_NAMES}",
                        el.tag, el.dim
                    ),
                )
            })?;
            match t {
                Target::Nodes(..) => node_targets.push(t.clone()),
                _ => {
                    if let Some(prev) = &element_target
                        && prev != t
                    {
                        return Err(gerr(
                            file,
                            el.pos,
                            format!(
                                "element {} is in two element groups ({:?} and {:?}); an element \
                                 may belong to one line or panel group only",
                                el.tag, prev, t
                            ),
                        ));
                    }
                    element_target = Some(t.clone());
                }
            }
        }
        for &tag in &el.nodes {
            if !by_tag.contains_key(&tag) {
                return Err(gerr(
                    file,
                    el.pos,
                    format!(
                        "element {} refers to node {tag}, which is not in $Nodes",
                        el.tag
                    ),
                ));
            }
        }
        kept.push(Kept {
            el,
            element_target,
            node_targets,
        });
    }
    if kept.is_empty() {
        return Err(gerr(
            file,
            FilePos::File,
            format!(
                "no usable physical group: {} element(s), none in a named physical group; define \
                 physical groups named {VALID_NAMES}",
                raw.elements.len()
            ),
        ));
    }
    if ignored > 0 {
        notices.push(format!(
            "warning: {obj}: {ignored} element(s) of {} are in no physical group and were ignored",
            file.display()
        ));
    }

    // Dense renumbering of used nodes, in file order.
    let mut used = vec![false; raw.nodes.len()];
    for k in &kept {
        for t in &k.el.nodes {
            used[by_tag[t]] = true;
        }
    }
    let mut b = MeshBuilder::default();
    let mut dense = vec![usize::MAX; raw.nodes.len()];
    let mut source_tags = Vec::new();
    for (i, n) in raw.nodes.iter().enumerate() {
        if used[i] {
            let p = r * (Vector3::from(n.x) * scale) + shift;
            dense[i] = b.add_node(Point3::from(p));
            source_tags.push(n.tag);
        }
    }
    let id = |tag: &u64| dense[by_tag[tag]];

    // Groups: element groups first (twines, panels, then others by first use), then nodes.
    let mut group_of: BTreeMap<(u8, String), usize> = BTreeMap::new();
    let mut order: Vec<Target> = Vec::new();
    for k in &kept {
        for t in k.element_target.iter().chain(k.node_targets.iter()) {
            if !order.contains(t) {
                order.push(t.clone());
            }
        }
    }
    let has_twines = order
        .iter()
        .any(|t| matches!(t, Target::Lines(_, Role::NetTwines)));
    let has_panels = order.contains(&Target::Panels);
    let rank = |t: &Target| match t {
        Target::Lines(_, Role::NetTwines) => 0,
        Target::Panels => 1,
        Target::Lines(..) => 2,
        Target::Nodes(..) => 3,
    };
    order.sort_by_key(rank);
    let mut tw_group = None;
    if has_panels && !has_twines {
        tw_group = Some(b.group("net_twines", Role::NetTwines, None));
    }
    for t in &order {
        let (key, gi) = match t {
            Target::Panels => (
                (1u8, "net_panels".to_string()),
                b.group("net_panels", Role::NetPanels, None),
            ),
            Target::Lines(n, role) => {
                let section = if *role == Role::NetTwines {
                    None
                } else {
                    Some(default_frame_section(n).unwrap_or_else(|| {
                        // Said only when the scene does not set the section itself.
                        if !params.groups.contains_key(n) {
                            notices.push(format!(
                            "notice: {obj}: line group `{n}` uses the rope default section (d = \
                             0.05 m, E = 1e9 Pa, 1100 kg/m³); set groups.{n} to change it"
                            ));
                        }
                        Section::cable("rope", 0.05, 1.0e9, 1100.0)
                    }))
                };
                let gi = b.group(n, *role, section);
                if *role == Role::NetTwines {
                    tw_group = Some(gi);
                }
                ((2u8, n.clone()), gi)
            }
            Target::Nodes(n, role) => ((3u8, n.clone()), b.group(n, *role, None)),
        };
        group_of.insert(key, gi);
    }
    let key_of = |t: &Target| match t {
        Target::Panels => (1u8, "net_panels".to_string()),
        Target::Lines(n, _) => (2u8, n.clone()),
        Target::Nodes(n, _) => (3u8, n.clone()),
    };

    // Elements.
    let mut node_sets: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for k in &kept {
        let el = k.el;
        let ids: Vec<usize> = el.nodes.iter().map(id).collect();
        if let Some(t) = &k.element_target {
            let g = group_of[&key_of(t)];
            match (t, el.kind) {
                (Target::Lines(..), 1) => {
                    let len = (b.mesh.nodes[ids[1]] - b.mesh.nodes[ids[0]]).norm();
                    if len <= 1e-12 {
                        return Err(gerr(
                            file,
                            el.pos,
                            format!(
                                "line element {} has zero length (nodes {:?})",
                                el.tag, el.nodes
                            ),
                        ));
                    }
                    b.add_line(g, ids[0], ids[1], None);
                }
                (Target::Panels, 2 | 3) => {
                    let pn = if el.kind == 2 {
                        PanelNodes::Tri([ids[0], ids[1], ids[2]])
                    } else {
                        PanelNodes::Quad([ids[0], ids[1], ids[2], ids[3]])
                    };
                    b.add_panel(g, pn);
                    let p = b.mesh.panels.len() - 1;
                    let area = b.mesh.panel_area(p);
                    if !(area >= 1e-12) {
                        return Err(gerr(
                            file,
                            el.pos,
                            format!(
                                "face element {} has area {area:e} m² < 1e-12 m² (degenerate)",
                                el.tag
                            ),
                        ));
                    }
                }
                (_, kind) => {
                    return Err(gerr(
                        file,
                        el.pos,
                        format!(
                            "element {} of type {kind} ({}) cannot be in group {:?}",
                            el.tag,
                            element_type_name(kind),
                            t
                        ),
                    ));
                }
            }
        }
        for t in &k.node_targets {
            node_sets
                .entry(group_of[&key_of(t)])
                .or_default()
                .extend(ids.iter().copied());
        }
    }
    // Derived twines: unique edges of the net faces.
    if let (Some(g), false) = (tw_group, has_twines) {
        let mut seen = BTreeSet::new();
        let faces: Vec<PanelNodes> = b.mesh.panels.iter().map(|p| p.nodes).collect();
        let triangles = faces.iter().any(|f| matches!(f, PanelNodes::Tri(_)));
        for f in faces {
            let n = f.as_slice();
            for i in 0..n.len() {
                let (a, c) = (n[i], n[(i + 1) % n.len()]);
                if seen.insert((a.min(c), a.max(c))) {
                    b.add_line(g, a, c, None);
                }
            }
        }
        notices.push(format!(
            "notice: {obj}: no `twines` group; {} net twines derived from the unique edges of \
             the net faces{}",
            seen.len(),
            if triangles {
                " (the edges of triangles included, so a triangulated quad mesh gets its \
                 diagonals as twines)"
            } else {
                ""
            }
        ));
    }
    b.finish_element_nodes();
    for (g, set) in node_sets {
        b.set_nodes(g, set);
    }
    // Section overrides.
    for (key, o) in &params.groups {
        match b
            .mesh
            .groups
            .iter_mut()
            .find(|g| &g.name == key && g.role.is_line_role())
        {
            Some(g) if g.role != Role::NetTwines => {
                if let Some(s) = g.section.as_mut() {
                    o.apply(obj, &format!("groups.{key}"), s)?;
                }
            }
            Some(_) => {}
            None => {
                let valid: Vec<&str> = b
                    .mesh
                    .groups
                    .iter()
                    .filter(|g| g.role.is_line_role())
                    .map(|g| g.name.as_str())
                    .collect();
                return Err(MeshError::UnknownGroup {
                    object: obj.to_string(),
                    key: format!("groups.{key}"),
                    name: key.clone(),
                    valid: valid.join(", "),
                });
            }
        }
    }
    // Net grouping.
    let net = match tw_group {
        Some(g) if !b.mesh.groups[g].lines.is_empty() => {
            let resolved = params.net.resolve(obj, &mut notices)?;
            let panels = b.mesh.groups.iter().position(|g| g.role == Role::NetPanels);
            let size = format!(
                "the file's `net` faces (`scale` = {})",
                params.scale.unwrap_or(1.0)
            );
            let grouping = resolved.group_net(&mut b, obj, g, panels, &size, &mut notices)?;
            let mut s = grouping.twine_section();
            if let Some(o) = params.groups.get("net_twines") {
                o.apply(obj, "groups.net_twines", &mut s)?;
            }
            b.mesh.groups[g].section = Some(s);
            if resolved.element == NetElement::Triangle {
                let panels = panels.ok_or_else(|| {
                    MeshError::param(
                        obj,
                        "net.element",
                        "triangle",
                        "needs net faces (a physical group `net` of dimension 2)",
                    )
                })?;
                let frame = TwineFrame::of(&resolved, TwineFrame::Horizontal { axis: origins[0] });
                make_net_triangles(&mut b, obj, &resolved, g, panels, frame)?;
            }
            Some(grouping)
        }
        _ => None,
    };
    b.mesh.objects.push(Object {
        name,
        kind: ObjectKind::Gmsh,
        origins: origins.clone(),
        net,
        detail: crate::model::ObjectDetail::Gmsh {
            source_node_tags: source_tags,
        },
    });
    b.mesh.notices = notices;
    let mut mesh = b.mesh;
    replicate(&mut mesh, &origins);
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classify_roles_and_dims() {
        assert_eq!(classify("net", 2), Ok(Target::Panels));
        assert!(classify("net", 1).is_err());
        assert_eq!(
            classify("line:bridle", 1),
            Ok(Target::Lines("bridle".into(), Role::UserLines))
        );
        assert!(classify("line:", 1).is_err());
        assert!(classify("fixed", 0).is_ok() && classify("fixed", 2).is_ok());
        assert!(classify("Net", 2).is_err());
    }
}
