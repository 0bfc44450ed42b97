//! The element lists an assembly is built from (net panels, lines, point bodies, wake groups)
//! and what it hands back per element and per call (element output, diagnostics, net summary).

use super::*;

/// The nodes of a net panel: a triangle or a (possibly warped) quad in cyclic order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PanelNodes {
    /// Mesh triangle (weight 1).
    Triangle([usize; 3]),
    /// Quad p1..p4, integrated as four triangles of weight ½.
    Quad([usize; 4]),
}

/// A net panel carrying screen-model drag and lift (no buoyancy: twines carry it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetPanel {
    /// Node indices.
    pub nodes: PanelNodes,
    /// Screen model, solidity and twine diameter.
    pub net: NetProps,
    /// Index of the cage copy (wake group) it belongs to, if any.
    pub wake_group: Option<usize>,
    /// The twine map of a net triangle, whose solidity then follows its twines
    /// (docs/theory/hydrodynamics.md#net-triangle-screen); `None`: `net.solidity` holds.
    pub twines: Option<TwineMap>,
}

/// A Morison line element (rope, pipe, chain, numerical net twine).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineElement {
    /// Node indices.
    pub nodes: [usize; 2],
    /// Section, model and coefficients.
    pub props: LineProps,
    /// True for numerical net twines: they belong to the net of their wake group (shadow
    /// test and centroid) and use c = 1 in Cheng's model.
    pub net_twine: bool,
    /// Cage copy it belongs to; ropes and pipes are reduced only if the group's wake has
    /// `apply_to_lines`.
    pub wake_group: Option<usize>,
}

/// A point body on one node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointElement {
    /// Node index.
    pub node: usize,
    /// Volume, height, drag area, added-mass coefficient.
    pub props: PointProps,
}

/// One cage copy for the wake: its wake model and net solidity.
#[derive(Debug, Clone, PartialEq)]
pub struct WakeGroup {
    /// Name for messages (e.g. "cage 1 copy 0").
    pub name: String,
    /// Wake configuration.
    pub wake: Wake,
    /// Net solidity Sn (Løland's C_D0 and Cheng's factor).
    pub solidity: f64,
}

/// Everything the assembly is built from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Elements {
    /// Net panels.
    pub panels: Vec<NetPanel>,
    /// Lines.
    pub lines: Vec<LineElement>,
    /// Point bodies.
    pub points: Vec<PointElement>,
    /// Wake groups referenced by panels and lines.
    pub wake_groups: Vec<WakeGroup>,
}

/// Dense output of one element, laid out like aqua-fem's `ElementLoad`: local node i,
/// component k → local DOF 3i + k.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementOutput {
    /// Force on each local node [N].
    pub force: [[f64; 3]; MAX_NODES],
    /// Added-mass block per local node [kg].
    pub added_mass: [Block; MAX_NODES],
    /// ∂f_{3i+k}/∂v_{3j+l} [N·s/m] (written if asked).
    pub dfdv: [[f64; MAX_DOFS]; MAX_DOFS],
    /// ∂f_{3i+k}/∂x_{3j+l} [N/m] (written if asked).
    pub dfdx: [[f64; MAX_DOFS]; MAX_DOFS],
}

impl Default for ElementOutput {
    fn default() -> Self {
        Self {
            force: [[0.0; 3]; MAX_NODES],
            added_mass: [[[0.0; 3]; 3]; MAX_NODES],
            dfdv: [[0.0; MAX_DOFS]; MAX_DOFS],
            dfdx: [[0.0; MAX_DOFS]; MAX_DOFS],
        }
    }
}

/// What the run has seen, for the log (warn once each).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Diagnostics {
    /// Range [min, max] of the twine Reynolds number s·dw0/ν over panels with flow.
    pub panel_reynolds: Option<[f64; 2]>,
    /// Range of s·d_Re/ν over lines with flow.
    pub line_reynolds: Option<[f64; 2]>,
    /// Some Reynolds number exceeded 1e7 and was clamped.
    pub reynolds_clamped: bool,
    /// S3/S6 saw Re₃ > 2e5 (drag crisis not modelled).
    pub cylinder_drag_crisis: bool,
    /// M5's X = Re·Sn² was capped at 100.
    pub m5_capped: bool,
}

/// Net area and twine volume of the panels and net twines (docs/theory/hydrodynamics.md#buoyancy,
/// log at start-up).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NetSummary {
    /// Σ weight·area of all panels [m²].
    pub area: f64,
    /// Σ A·(π/4)·dw0·Sn over panels [m³]: the physical twine volume.
    pub expected_twine_volume: f64,
    /// Σ (π/4)·d_v²·L0 over net-twine lines [m³]: the volume that carries net buoyancy.
    pub twine_volume: f64,
}
