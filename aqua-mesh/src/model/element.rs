//! The elements of a mesh: groups, 2-node line elements, net panels and point weights.

use crate::model::Role;
use crate::section::Section;
use serde::Serialize;

/// A named group of one object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Group {
    /// Group name (`net_twines`, `top_ring`, a user name, …).
    pub name: String,
    /// What the group is for.
    pub role: Role,
    /// Index of the owning object in [`Mesh::objects`](crate::Mesh::objects).
    pub object: u32,
    /// Line elements of the group (indices into [`Mesh::lines`](crate::Mesh::lines)), empty for node/panel groups.
    pub lines: Vec<usize>,
    /// Panels of the group (indices into [`Mesh::panels`](crate::Mesh::panels)).
    pub panels: Vec<usize>,
    /// Nodes of the group, sorted and unique. For line and panel groups: all their nodes.
    pub nodes: Vec<usize>,
    /// Section of a line group (`None` for node and panel groups).
    pub section: Option<Section>,
}

/// A 2-node line element.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineElement {
    /// End nodes `[a, b]`.
    pub nodes: [usize; 2],
    /// Index of its (element) group in [`Mesh::groups`](crate::Mesh::groups).
    pub group: usize,
    /// Owning object.
    pub object: u32,
    /// Copy index of a multi-origin object.
    pub copy: u32,
    /// Unstretched length L0 [m] when the builder sets it (single lines); `None` = as built.
    pub rest_length: Option<f64>,
    /// How many of its group's sections the element stands for (1 for most elements): its
    /// axial stiffness, mass, displaced volume and Morison drag area are this multiple of the
    /// group section's. Net twines: λ_e/λ̄ (docs/theory/cages.md#mesh-grouping); CCT/CCS
    /// ropes: design ropes per rope column (docs/theory/cages.md#frame-ropes-and-weights).
    pub section_scale: f64,
}

/// Corner nodes of a net panel, in cyclic order (valid VTK order), normal by the right-hand rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum PanelNodes {
    /// 3-node triangle.
    Tri([usize; 3]),
    /// 4-node quadrilateral.
    Quad([usize; 4]),
}

impl PanelNodes {
    /// The corner nodes as a slice.
    pub fn as_slice(&self) -> &[usize] {
        match self {
            PanelNodes::Tri(n) => n,
            PanelNodes::Quad(n) => n,
        }
    }
}

/// A net panel (screen element).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Panel {
    /// Corner nodes.
    pub nodes: PanelNodes,
    /// Index of its group in [`Mesh::groups`](crate::Mesh::groups).
    pub group: usize,
    /// Owning object.
    pub object: u32,
    /// Copy index.
    pub copy: u32,
    /// Mesh coordinates (U, V) of the corners of a net triangle [half meshes]
    /// (docs/theory/fem.md#net-triangle); `None` for a screen panel on a cable net.
    pub uv: Option<[[f64; 2]; 3]>,
}

/// A point weight (sinker, tip weight, centre weight) on one node: a point body of mass W/g and
/// zero volume (docs/theory/fem.md#loads).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointWeight {
    /// Node carrying the weight.
    pub node: usize,
    /// Submerged weight W [N] (downward force), ≥ 0.
    pub weight: f64,
    /// Node group the weight was defined on (`sinkers`, `tip`, `centre_weight`, `panel_bottom`).
    pub group: usize,
}
