//! Roles of groups: what the downstream models do with a group.

use serde::Serialize;

/// Role of a group: what the downstream models do with it (docs/theory/cages.md#groups-produced,
/// #flat-net-panel, #single-line, #gmsh-import).
///
/// The numeric value ([`Role::id`]) is written to VTK as `role_id`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Net twine cables (λ-grouped, docs/theory/cages.md#mesh-grouping). Lines.
    NetTwines,
    /// Hydrodynamic screen panels (quads and triangles). Faces.
    NetPanels,
    /// Collar ring (lines and its nodes).
    TopRing,
    /// Links from the net's top edge to the collar. Lines.
    TopLinks,
    /// Rope columns (and CCS bottom ropes). Lines.
    Ropes,
    /// Net-to-rope ties. Lines.
    TieLines,
    /// CCT sinker tube. Lines and nodes.
    BottomRing,
    /// A mooring line or bridle from the single-line builder. Lines.
    MooringLine,
    /// A user cable group from gmsh (`line:<name>`). Lines.
    UserLines,
    /// All net nodes. Nodes.
    NetNodes,
    /// Net level 0 (top edge). Nodes.
    NetTop,
    /// Net level NN (side bottom). Nodes.
    NetBottom,
    /// Cone tip. One node.
    Tip,
    /// Nodes that carry sinker weights. Nodes.
    Sinkers,
    /// CCS central sinker. One node.
    CentreWeight,
    /// All rope-column nodes. Nodes.
    FrameNodes,
    /// Nodes held fixed in all DOFs (unless the scene overrides). Nodes.
    Fixed,
    /// Anchor end of a line. One node.
    Anchor,
    /// Fairlead end of a line. One node.
    Fairlead,
    /// All nodes of a line. Nodes.
    LineNodes,
    /// Panel builder edges: top (j = 0). Nodes.
    PanelTop,
    /// Panel builder edges: bottom (j = n_h). Nodes.
    PanelBottom,
    /// Panel builder edges: left (i = 0). Nodes.
    PanelLeft,
    /// Panel builder edges: right (i = n_w). Nodes.
    PanelRight,
    /// A user node group from gmsh (`nodes:<name>`). Nodes.
    UserNodes,
    /// Outer pipe of a two-pipe collar (docs/theory/cages.md#collar). Lines.
    OuterRing,
    /// Brackets joining the two pipes of a collar. Lines.
    Brackets,
    /// Coupling plates of a farm grid (where frame lines, bridles and anchor lines meet).
    /// Nodes.
    Plates,
    /// Buoy nodes of a farm grid. Nodes.
    Buoys,
}

impl Role {
    /// All roles, in id order.
    pub const ALL: [Role; 29] = [
        Role::NetTwines,
        Role::NetPanels,
        Role::TopRing,
        Role::TopLinks,
        Role::Ropes,
        Role::TieLines,
        Role::BottomRing,
        Role::MooringLine,
        Role::UserLines,
        Role::NetNodes,
        Role::NetTop,
        Role::NetBottom,
        Role::Tip,
        Role::Sinkers,
        Role::CentreWeight,
        Role::FrameNodes,
        Role::Fixed,
        Role::Anchor,
        Role::Fairlead,
        Role::LineNodes,
        Role::PanelTop,
        Role::PanelBottom,
        Role::PanelLeft,
        Role::PanelRight,
        Role::UserNodes,
        Role::OuterRing,
        Role::Brackets,
        Role::Plates,
        Role::Buoys,
    ];

    /// Stable numeric id (written to VTK `role_id`).
    pub fn id(self) -> u32 {
        Role::ALL.iter().position(|&r| r == self).unwrap_or(0) as u32
    }

    /// The default group name of this role (`net_twines`, `top_ring`, …).
    pub fn default_name(self) -> &'static str {
        match self {
            Role::NetTwines => "net_twines",
            Role::NetPanels => "net_panels",
            Role::TopRing => "top_ring",
            Role::TopLinks => "top_links",
            Role::Ropes => "ropes",
            Role::TieLines => "tie_lines",
            Role::BottomRing => "bottom_ring",
            Role::MooringLine => "line",
            Role::UserLines => "user_lines",
            Role::NetNodes => "net_nodes",
            Role::NetTop => "net_top",
            Role::NetBottom => "net_bottom",
            Role::Tip => "tip",
            Role::Sinkers => "sinkers",
            Role::CentreWeight => "centre_weight",
            Role::FrameNodes => "frame_nodes",
            Role::Fixed => "fixed",
            Role::Anchor => "anchor",
            Role::Fairlead => "fairlead",
            Role::LineNodes => "line_nodes",
            Role::PanelTop => "panel_top",
            Role::PanelBottom => "panel_bottom",
            Role::PanelLeft => "panel_left",
            Role::PanelRight => "panel_right",
            Role::UserNodes => "user_nodes",
            Role::OuterRing => "outer_ring",
            Role::Brackets => "brackets",
            Role::Plates => "plates",
            Role::Buoys => "buoys",
        }
    }

    /// True for roles whose groups hold line elements (cables or bars).
    pub fn is_line_role(self) -> bool {
        matches!(
            self,
            Role::NetTwines
                | Role::TopRing
                | Role::TopLinks
                | Role::Ropes
                | Role::TieLines
                | Role::BottomRing
                | Role::MooringLine
                | Role::UserLines
                | Role::OuterRing
                | Role::Brackets
        )
    }

    /// True for the panel role.
    pub fn is_panel_role(self) -> bool {
        self == Role::NetPanels
    }
}
