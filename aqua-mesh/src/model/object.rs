//! Objects in a mesh: what built each object and what its builder keeps (net
//! grouping, one `ObjectDetail`: cage counts, gmsh node tags). The builders fill these
//! descriptions; the model needs none of them.

use crate::model::NetGrouping;
use serde::{Deserialize, Serialize};

/// Cage type code (`type` key).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
pub enum CageType {
    /// Circular, conical wall, sinker tube.
    #[serde(rename = "CCT")]
    Cct,
    /// Circular, conical wall, central sinker.
    #[serde(rename = "CCS")]
    Ccs,
    /// Circular, straight wall, sinker masses.
    #[serde(rename = "CSM")]
    Csm,
    /// Square, straight wall, sinker masses.
    #[serde(rename = "SSM")]
    Ssm,
    /// Alias of CCT (a notice recommends CCT).
    #[serde(rename = "CST")]
    Cst,
}

impl CageType {
    /// The code as written in the scene (`CCT`, …).
    pub fn code(self) -> &'static str {
        match self {
            CageType::Cct => "CCT",
            CageType::Ccs => "CCS",
            CageType::Csm => "CSM",
            CageType::Ssm => "SSM",
            CageType::Cst => "CST",
        }
    }

    /// Parse a code (case-insensitive).
    pub fn from_code(s: &str) -> Option<Self> {
        match s.to_ascii_uppercase().as_str() {
            "CCT" => Some(CageType::Cct),
            "CCS" => Some(CageType::Ccs),
            "CSM" => Some(CageType::Csm),
            "SSM" => Some(CageType::Ssm),
            "CST" => Some(CageType::Cst),
            _ => None,
        }
    }

    /// CST → CCT; others unchanged.
    pub fn canonical(self) -> Self {
        if self == CageType::Cst {
            CageType::Cct
        } else {
            self
        }
    }
}

/// Kind of object a builder produced.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectKind {
    /// A parametric cage.
    Cage(CageType),
    /// A flat net panel.
    Panel,
    /// A single line.
    Line,
    /// A mesh imported from gmsh.
    Gmsh,
    /// The node of a free buoy.
    Buoy,
    /// The frame of a farm grid (frame lines, bridles, pendants, plates, buoys).
    Frame,
    /// The points a free rigid body holds: its hull's columns and its named points.
    Body,
}

/// Discretisation numbers of a cage (docs/theory/cages.md#discretisation-counts).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CageCounts {
    /// Nodes around the circumference NT.
    pub nt: usize,
    /// Side segments NN.
    pub nn: usize,
    /// Cone segments BN.
    pub bn: usize,
    /// Frame extension segments (n_x, n_t or n_b; 0 if not used).
    pub n_ext: usize,
    /// Physical ropes of the design (CCT, CCS: the `ropes` key; CSM, SSM: NT, one per column).
    pub ropes: usize,
    /// Top radius (circular) or half-width (square) R_t / h [m].
    pub top_radius: f64,
    /// Bottom radius R_b (square: h) [m].
    pub bottom_radius: f64,
    /// Actual element length around the top ring [m].
    pub ring_element_length: f64,
    /// Actual element length along the side meridians [m].
    pub side_element_length: f64,
    /// Actual element length along the cone meridians (first cone segment) [m].
    pub cone_element_length: f64,
}

/// One object (cage, panel, line, imported mesh) in a mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Object {
    /// Object name (`cage0`, …).
    pub name: String,
    /// What built it.
    pub kind: ObjectKind,
    /// Origins of its copies (one per copy) [m].
    pub origins: Vec<[f64; 3]>,
    /// Net parameters and mesh-grouping numbers, if the object has a net.
    pub net: Option<NetGrouping>,
    /// What its builder keeps about it beyond the mesh (none for most builders).
    pub detail: ObjectDetail,
}

/// What a builder keeps about an object beyond its nodes and elements: one slot, so the object
/// carries no field that only one builder fills, and a builder that keeps nothing adds nothing.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectDetail {
    /// Nothing.
    #[default]
    None,
    /// A parametric cage's discretisation numbers.
    Cage(CageCounts),
    /// An import's original gmsh node tags of copy 0, in dense node order.
    Gmsh {
        /// The tags.
        source_node_tags: Vec<u64>,
    },
}

impl Object {
    /// The cage discretisation numbers (cages only).
    pub fn counts(&self) -> Option<&CageCounts> {
        match &self.detail {
            ObjectDetail::Cage(c) => Some(c),
            _ => None,
        }
    }

    /// The original gmsh node tags of copy 0 (imports only; empty otherwise).
    pub fn source_node_tags(&self) -> &[u64] {
        match &self.detail {
            ObjectDetail::Gmsh { source_node_tags } => source_node_tags,
            _ => &[],
        }
    }
}
