//! Summaries of a mesh for reports (`aqua mesh`, logs): counts per group, λ and diameters per
//! object.

use crate::model::{CageCounts, Mesh, NetGrouping, ObjectKind, PanelNodes, Role};
use serde::Serialize;

impl Mesh {
    /// Summary for reports (`aqua mesh`, logs): counts per group, λ and diameters per object.
    pub fn summary(&self) -> MeshSummary {
        MeshSummary {
            nodes: self.nodes.len(),
            lines: self.lines.len(),
            panels: self.panels.len(),
            quads: self
                .panels
                .iter()
                .filter(|p| matches!(p.nodes, PanelNodes::Quad(_)))
                .count(),
            triangles: self
                .panels
                .iter()
                .filter(|p| matches!(p.nodes, PanelNodes::Tri(_)))
                .count(),
            total_weight: self.weights.iter().fold(0.0, |a, w| a + w.weight),
            objects: self
                .objects
                .iter()
                .enumerate()
                .map(|(i, o)| ObjectSummary {
                    name: o.name.clone(),
                    kind: match &o.kind {
                        ObjectKind::Cage(t) => t.code().to_string(),
                        ObjectKind::Panel => "panel".into(),
                        ObjectKind::Line => "line".into(),
                        ObjectKind::Gmsh => "gmsh".into(),
                        ObjectKind::Buoy => "buoy".into(),
                        ObjectKind::Frame => "frame".into(),
                        ObjectKind::Body => "body".into(),
                    },
                    copies: o.origins.len(),
                    counts: o.counts().cloned(),
                    net: o.net.clone(),
                    groups: self
                        .groups
                        .iter()
                        .filter(|g| g.object as usize == i)
                        .map(|g| GroupSummary {
                            name: g.name.clone(),
                            role: g.role,
                            role_id: g.role.id(),
                            lines: g.lines.len(),
                            panels: g.panels.len(),
                            nodes: g.nodes.len(),
                            weight: self
                                .weights
                                .iter()
                                .filter(|w| self.groups[w.group].name == g.name)
                                .filter(|w| self.groups[w.group].object == g.object)
                                .fold(0.0, |a, w| a + w.weight),
                            diameter: g.section.as_ref().map(|s| s.diameter),
                            elastic_diameter: g.section.as_ref().map(|s| s.elastic_diameter),
                            hydro_diameter: g.section.as_ref().map(|s| s.hydro_diameter),
                        })
                        .collect(),
                })
                .collect(),
            notices: self.notices.clone(),
        }
    }
}

/// Serializable summary of a mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshSummary {
    /// Node count.
    pub nodes: usize,
    /// Line element count.
    pub lines: usize,
    /// Panel count.
    pub panels: usize,
    /// Quad panels.
    pub quads: usize,
    /// Triangle panels.
    pub triangles: usize,
    /// Sum of point weights [N].
    pub total_weight: f64,
    /// Per object.
    pub objects: Vec<ObjectSummary>,
    /// Warnings and notices.
    pub notices: Vec<String>,
}

/// Summary of one object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObjectSummary {
    /// Name.
    pub name: String,
    /// `SSM`, `panel`, `line`, `gmsh`, …
    pub kind: String,
    /// Number of copies.
    pub copies: usize,
    /// Cage discretisation numbers.
    pub counts: Option<CageCounts>,
    /// Net parameters, λ and diameters.
    pub net: Option<NetGrouping>,
    /// Per group.
    pub groups: Vec<GroupSummary>,
}

/// Counts of one group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupSummary {
    /// Name.
    pub name: String,
    /// Role.
    pub role: Role,
    /// Numeric role id.
    pub role_id: u32,
    /// Line elements.
    pub lines: usize,
    /// Panels.
    pub panels: usize,
    /// Nodes.
    pub nodes: usize,
    /// Point weight defined on this group [N].
    pub weight: f64,
    /// Structural diameter [m] (line groups).
    pub diameter: Option<f64>,
    /// Elastic diameter [m].
    pub elastic_diameter: Option<f64>,
    /// Hydrodynamic diameter [m].
    pub hydro_diameter: Option<f64>,
}
