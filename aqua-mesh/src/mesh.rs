//! The mesh: nodes, 2-node line elements, net panels, named groups by role, point weights.
//!
//! Ids are dense indices into the vectors of [`Mesh`] and follow the normative ordering of
//! docs/theory/cages.md#net-geometry and #frame-ropes-and-weights. Several objects (cages, panels,
//! lines, imported meshes) can live in one mesh ([`Mesh::append`]); every group belongs to one
//! object, and every entity records its `(object, copy)` (copy = index of the origin of a
//! multi-origin cage).

use crate::net::NetGrouping;
use nalgebra::{Point3, Vector3};
use serde::Serialize;
use std::collections::BTreeSet;

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

/// Compression ratio of tension-only members (twines, ropes, chains): a slack member carries
/// no force at all, so slack costs nothing in the answer (docs/theory/fem.md#slack-members).
/// A ratio of 1e-4, the earlier default, let slack twines push and raised the reference
/// cage's drag by 2.5 %.
pub const TENSION_ONLY: f64 = 0.0;

/// Section and material of a line group (keys of docs/theory/fem.md#sections).
///
/// Diameters in m, modulus in Pa, density in kg/m³. For net twines the three diameters come from
/// mesh grouping (docs/theory/cages.md#mesh-grouping): `diameter` = dws, `elastic_diameter` = dwe,
/// `hydro_diameter` = dwh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// Material label (informative), e.g. `nylon`, `rope`, `HDPE pipe`.
    pub material: String,
    /// Structural (outer) diameter d [m]: mass, buoyancy volume, contact width.
    pub diameter: f64,
    /// Pipe wall thickness [m]; `None` for a solid section.
    pub wall_thickness: Option<f64>,
    /// Diameter giving the axial stiffness, EA = E·π/4·d_e² (solid) [m].
    pub elastic_diameter: f64,
    /// Diameter for Morison drag [m].
    pub hydro_diameter: f64,
    /// Diameter of the displaced volume [m] (sealed pipe: outer diameter).
    pub volume_diameter: f64,
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Material density ρ_s [kg/m³].
    pub density: f64,
    /// Compression ratio r_c (docs/theory/fem.md#slack-members): 0 for tension-only cables
    /// (default, [`TENSION_ONLY`]), 1 for bars/pipes.
    pub compression_ratio: f64,
    /// Explicit EA [N] overriding E·A.
    pub ea: Option<f64>,
    /// Explicit mass per length μ [kg/m] overriding ρ_s·A.
    pub mass_per_length: Option<f64>,
    /// Axial damping c_a [N·s] (docs/theory/fem.md#cable-element); `None` = no damping unless a
    /// ratio is given.
    pub axial_damping: Option<f64>,
    /// Axial damping ratio ζ (docs/theory/fem.md#cable-element).
    pub axial_damping_ratio: Option<f64>,
    /// Initial tension T0 [N] (docs/theory/fem.md#cable-element), default 0.
    pub initial_tension: f64,
    /// Seabed contact on/off (default on).
    pub seabed: bool,
    /// Seabed contact width [m]; `None` = `volume_diameter`.
    pub contact_diameter: Option<f64>,
    /// Bending on/off (docs/theory/fem.md#bending-of-sections); `None` = automatic: on for a
    /// pipe (`wall_thickness` set) or when `ei` is given, off for a solid section.
    pub bending: Option<bool>,
    /// Explicit bending stiffness EI [N·m²] overriding E·I.
    pub ei: Option<f64>,
    /// The element that carries the bending (docs/theory/fem.md#bending-of-sections).
    pub bending_element: BendingElement,
    /// Poisson's ratio ν for the shear modulus G = E/(2(1 + ν)) of the torsional stiffness.
    pub poisson_ratio: f64,
}

/// Poisson's ratio of the pipes' polyethylene (HDPE ≈ 0.4–0.46), the default ν of a section.
pub const DEFAULT_POISSON_RATIO: f64 = 0.4;

/// The element that carries a section's bending (docs/theory/fem.md#bending-of-sections).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BendingElement {
    /// Discrete elastic rod: bending about both axes in a material frame, and torsion
    /// (docs/theory/fem.md#rod). The default.
    #[default]
    Rod,
    /// Rotation-free hinge on three nodes: bending magnitude only, no torsion
    /// (docs/theory/fem.md#bending); cheaper, safe for members built straight.
    Hinge,
}

impl BendingElement {
    /// The key value.
    pub fn as_str(self) -> &'static str {
        match self {
            BendingElement::Rod => "rod",
            BendingElement::Hinge => "hinge",
        }
    }
}

impl Section {
    /// Tension-only cable section of solid diameter `d` [m].
    pub fn cable(material: &str, d: f64, youngs_modulus: f64, density: f64) -> Self {
        Section {
            material: material.to_string(),
            diameter: d,
            wall_thickness: None,
            elastic_diameter: d,
            hydro_diameter: d,
            volume_diameter: d,
            youngs_modulus,
            density,
            compression_ratio: TENSION_ONLY,
            ea: None,
            mass_per_length: None,
            axial_damping: None,
            axial_damping_ratio: None,
            initial_tension: 0.0,
            seabed: true,
            contact_diameter: None,
            bending: None,
            ei: None,
            bending_element: BendingElement::Rod,
            poisson_ratio: DEFAULT_POISSON_RATIO,
        }
    }

    /// Sealed pipe (bar carrying compression) of outer diameter `d` and wall `t` [m].
    pub fn pipe(material: &str, d: f64, t: f64, youngs_modulus: f64, density: f64) -> Self {
        Section {
            material: material.to_string(),
            diameter: d,
            wall_thickness: Some(t),
            elastic_diameter: d,
            hydro_diameter: d,
            volume_diameter: d,
            youngs_modulus,
            density,
            compression_ratio: 1.0,
            ea: None,
            mass_per_length: None,
            axial_damping: None,
            axial_damping_ratio: None,
            initial_tension: 0.0,
            seabed: true,
            contact_diameter: None,
            bending: None,
            ei: None,
            bending_element: BendingElement::Rod,
            poisson_ratio: DEFAULT_POISSON_RATIO,
        }
    }

    /// Material cross-section area for the stiffness [m²]: π/4·d_e² for a solid section,
    /// π/4·(D² − (D − 2t)²) for a pipe.
    pub fn stiffness_area(&self) -> f64 {
        let d = self.elastic_diameter;
        match self.wall_thickness {
            Some(t) => std::f64::consts::FRAC_PI_4 * (d * d - (d - 2.0 * t).powi(2)),
            None => std::f64::consts::FRAC_PI_4 * d * d,
        }
    }

    /// Material cross-section area for the mass [m²] (uses `diameter`).
    pub fn mass_area(&self) -> f64 {
        let d = self.diameter;
        match self.wall_thickness {
            Some(t) => std::f64::consts::FRAC_PI_4 * (d * d - (d - 2.0 * t).powi(2)),
            None => std::f64::consts::FRAC_PI_4 * d * d,
        }
    }

    /// Axial stiffness EA [N].
    pub fn axial_stiffness(&self) -> f64 {
        self.ea
            .unwrap_or(self.youngs_modulus * self.stiffness_area())
    }

    /// Mass per unit length μ [kg/m].
    pub fn linear_mass(&self) -> f64 {
        self.mass_per_length
            .unwrap_or(self.density * self.mass_area())
    }

    /// Second moment of area of the stiffness section [m⁴]: π/64·d_e⁴ (solid) or
    /// π/64·(D⁴ − (D − 2t)⁴) (pipe), with d_e = `elastic_diameter`.
    pub fn second_moment(&self) -> f64 {
        let d = self.elastic_diameter;
        let c = std::f64::consts::PI / 64.0;
        match self.wall_thickness {
            Some(t) => c * (d.powi(4) - (d - 2.0 * t).max(0.0).powi(4)),
            None => c * d.powi(4),
        }
    }

    /// True if the group bends: `bending` if set, otherwise on for pipes and when `ei` is
    /// given (docs/theory/fem.md#bending-of-sections).
    pub fn bends(&self) -> bool {
        self.bending
            .unwrap_or(self.wall_thickness.is_some() || self.ei.is_some())
    }

    /// Bending stiffness EI [N·m²]: 0 if the section does not bend, else `ei` or E·I.
    pub fn bending_stiffness(&self) -> f64 {
        if !self.bends() {
            return 0.0;
        }
        self.ei
            .unwrap_or(self.youngs_modulus * self.second_moment())
    }

    /// Torsional stiffness GJ [N·m²] of a round section, J = 2I: GJ = EI/(1 + ν), with the
    /// bending stiffness as given (`ei` or E·I).
    pub fn torsional_stiffness(&self) -> f64 {
        self.bending_stiffness() / (1.0 + self.poisson_ratio)
    }

    /// Spin inertia per unit length μ·r_g² [kg·m], r_g² = (D² + d_i²)/8 for a pipe of inner
    /// diameter d_i = D − 2t, D²/8 for a solid section.
    pub fn spin_inertia(&self) -> f64 {
        let d = self.diameter;
        let di = self.wall_thickness.map_or(0.0, |t| (d - 2.0 * t).max(0.0));
        self.linear_mass() * (d * d + di * di) / 8.0
    }

    /// Largest fibre stress |N|/A + |M|·(d_e/2)/I [Pa] of the stiffness section under axial
    /// force N [N] and bending moment M [N·m] (docs/theory/fem.md#rod).
    pub fn fibre_stress(&self, axial: f64, moment: f64) -> f64 {
        let i = self.second_moment();
        let bend = if i > 0.0 {
            moment.abs() * 0.5 * self.elastic_diameter / i
        } else {
            0.0
        };
        axial.abs() / self.stiffness_area() + bend
    }
}

/// A named group of one object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Group {
    /// Group name (`net_twines`, `top_ring`, a user name, …).
    pub name: String,
    /// What the group is for.
    pub role: Role,
    /// Index of the owning object in [`Mesh::objects`].
    pub object: u32,
    /// Line elements of the group (indices into [`Mesh::lines`]), empty for node/panel groups.
    pub lines: Vec<usize>,
    /// Panels of the group (indices into [`Mesh::panels`]).
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
    /// Index of its (element) group in [`Mesh::groups`].
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
    /// Index of its group in [`Mesh::groups`].
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

/// Kind of object a builder produced.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectKind {
    /// A parametric cage.
    Cage(crate::cage::CageType),
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
    /// Cage discretisation numbers (cages only).
    pub counts: Option<CageCounts>,
    /// Original gmsh node tags of copy 0, in dense node order (imports only).
    pub source_node_tags: Vec<u64>,
}

/// Nodes, elements, panels, groups and weights of one or several objects.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Node positions [m].
    pub nodes: Vec<Point3<f64>>,
    /// `(object, copy)` of every node.
    pub node_owner: Vec<(u32, u32)>,
    /// Line elements.
    pub lines: Vec<LineElement>,
    /// Net panels.
    pub panels: Vec<Panel>,
    /// Groups of all objects.
    pub groups: Vec<Group>,
    /// Objects.
    pub objects: Vec<Object>,
    /// Point weights.
    pub weights: Vec<PointWeight>,
    /// Warnings and notices produced while building (λ > 500, CST alias, …).
    pub notices: Vec<String>,
}

impl Mesh {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Iterate over line elements with their index.
    pub fn iter_lines(&self) -> impl Iterator<Item = (usize, &LineElement)> {
        self.lines.iter().enumerate()
    }

    /// Iterate over panels with their index.
    pub fn iter_panels(&self) -> impl Iterator<Item = (usize, &Panel)> {
        self.panels.iter().enumerate()
    }

    /// All groups with this name (one per object that has it).
    pub fn groups_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Group> + 'a {
        self.groups.iter().filter(move |g| g.name == name)
    }

    /// All groups with this role.
    pub fn groups_with_role(&self, role: Role) -> impl Iterator<Item = &Group> + '_ {
        self.groups.iter().filter(move |g| g.role == role)
    }

    /// The group `name` of object `object`.
    pub fn group(&self, object: u32, name: &str) -> Option<&Group> {
        self.groups
            .iter()
            .find(|g| g.object == object && g.name == name)
    }

    /// Index of the group `name` of object `object`.
    pub fn group_index(&self, object: u32, name: &str) -> Option<usize> {
        self.groups
            .iter()
            .position(|g| g.object == object && g.name == name)
    }

    /// Resolve a scene group reference: `<group>` (all objects), `<name>/<group>` (one object)
    /// or `<name>#<k>/<group>` (copy k). The group name is what follows the last `/`, so object
    /// names may hold `/` (a farm's `farm/cage_r1c2`). Returns the node ids, sorted and unique;
    /// `None` if no group matches.
    pub fn resolve_nodes(&self, reference: &str) -> Option<Vec<usize>> {
        let (obj, copy, group) = match reference.rsplit_once('/') {
            None => (None, None, reference),
            Some((o, g)) => match o.split_once('#') {
                Some((name, k)) => (Some(name), Some(k.parse::<u32>().ok()?), g),
                None => (Some(o), None, g),
            },
        };
        let mut found = false;
        let mut set = BTreeSet::new();
        for g in &self.groups {
            if g.name != group {
                continue;
            }
            if let Some(o) = obj
                && self.objects[g.object as usize].name != o
            {
                continue;
            }
            found = true;
            set.extend(
                g.nodes
                    .iter()
                    .copied()
                    .filter(|&n| copy.is_none_or(|c| self.node_owner[n].1 == c)),
            );
        }
        found.then(|| set.into_iter().collect())
    }

    /// Nodes held fixed: union of all `fixed` groups.
    pub fn fixed_nodes(&self) -> Vec<usize> {
        let mut set = BTreeSet::new();
        for g in self.groups_with_role(Role::Fixed) {
            set.extend(g.nodes.iter().copied());
        }
        set.into_iter().collect()
    }

    /// Current length of line element `e` [m].
    pub fn line_length(&self, e: usize) -> f64 {
        let [a, b] = self.lines[e].nodes;
        (self.nodes[b] - self.nodes[a]).norm()
    }

    /// Area of panel `p` [m²] (quads: half the norm of the cross product of the diagonals, exact
    /// for planar quads).
    pub fn panel_area(&self, p: usize) -> f64 {
        self.panel_area_vector(p).norm()
    }

    /// Area vector of panel `p` (area × unit normal, right-hand rule over the node order) [m²].
    pub fn panel_area_vector(&self, p: usize) -> Vector3<f64> {
        let x = |i: usize| self.nodes[i];
        match self.panels[p].nodes {
            PanelNodes::Tri([a, b, c]) => 0.5 * (x(b) - x(a)).cross(&(x(c) - x(a))),
            PanelNodes::Quad([a, b, c, d]) => 0.5 * (x(c) - x(a)).cross(&(x(d) - x(b))),
        }
    }

    /// Total number of VTK cells: lines first, then panels.
    pub fn cell_count(&self) -> usize {
        self.lines.len() + self.panels.len()
    }

    /// Append another mesh (ids of `other` are offset; its objects get new indices).
    /// Returns the node offset applied to `other`'s node ids.
    pub fn append(&mut self, other: Mesh) -> usize {
        let node_off = self.nodes.len();
        let line_off = self.lines.len();
        let panel_off = self.panels.len();
        let group_off = self.groups.len();
        let obj_off = self.objects.len() as u32;
        self.nodes.extend(other.nodes);
        self.node_owner
            .extend(other.node_owner.into_iter().map(|(o, c)| (o + obj_off, c)));
        self.lines.extend(other.lines.into_iter().map(|mut l| {
            l.nodes = l.nodes.map(|n| n + node_off);
            l.group += group_off;
            l.object += obj_off;
            l
        }));
        self.panels.extend(other.panels.into_iter().map(|mut p| {
            p.nodes = match p.nodes {
                PanelNodes::Tri(n) => PanelNodes::Tri(n.map(|i| i + node_off)),
                PanelNodes::Quad(n) => PanelNodes::Quad(n.map(|i| i + node_off)),
            };
            p.group += group_off;
            p.object += obj_off;
            p
        }));
        self.groups.extend(other.groups.into_iter().map(|mut g| {
            g.object += obj_off;
            g.lines.iter_mut().for_each(|e| *e += line_off);
            g.panels.iter_mut().for_each(|e| *e += panel_off);
            g.nodes.iter_mut().for_each(|e| *e += node_off);
            g
        }));
        self.weights.extend(other.weights.into_iter().map(|mut w| {
            w.node += node_off;
            w.group += group_off;
            w
        }));
        self.objects.extend(other.objects);
        self.notices.extend(other.notices);
        node_off
    }

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
                    },
                    copies: o.origins.len(),
                    counts: o.counts.clone(),
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

/// Incremental builder used by the parametric builders.
#[derive(Debug, Default)]
pub(crate) struct MeshBuilder {
    pub mesh: Mesh,
}

impl MeshBuilder {
    pub fn add_node(&mut self, p: Point3<f64>) -> usize {
        self.mesh.nodes.push(p);
        self.mesh.node_owner.push((0, 0));
        self.mesh.nodes.len() - 1
    }

    /// New empty group of object 0; returns its index.
    pub fn group(&mut self, name: &str, role: Role, section: Option<Section>) -> usize {
        self.mesh.groups.push(Group {
            name: name.to_string(),
            role,
            object: 0,
            lines: Vec::new(),
            panels: Vec::new(),
            nodes: Vec::new(),
            section,
        });
        self.mesh.groups.len() - 1
    }

    /// Index of the (first) group named `name`; the builders only ask for groups they made.
    pub fn group_index_of(&self, name: &str) -> usize {
        self.mesh
            .groups
            .iter()
            .position(|g| g.name == name)
            .unwrap_or(0)
    }

    pub fn add_line(&mut self, group: usize, a: usize, b: usize, rest_length: Option<f64>) {
        self.mesh.lines.push(LineElement {
            nodes: [a, b],
            group,
            object: 0,
            copy: 0,
            rest_length,
            section_scale: 1.0,
        });
        self.mesh.groups[group]
            .lines
            .push(self.mesh.lines.len() - 1);
    }

    pub fn add_panel(&mut self, group: usize, nodes: PanelNodes) {
        self.mesh.panels.push(Panel {
            nodes,
            group,
            object: 0,
            copy: 0,
            uv: None,
        });
        self.mesh.groups[group]
            .panels
            .push(self.mesh.panels.len() - 1);
    }

    pub fn set_nodes(&mut self, group: usize, nodes: impl IntoIterator<Item = usize>) {
        let set: BTreeSet<usize> = nodes.into_iter().collect();
        self.mesh.groups[group].nodes = set.into_iter().collect();
    }

    /// Fill `nodes` of every line/panel group from its elements.
    pub fn finish_element_nodes(&mut self) {
        let m = &mut self.mesh;
        for g in m.groups.iter_mut() {
            if g.lines.is_empty() && g.panels.is_empty() {
                continue;
            }
            let mut set = BTreeSet::new();
            for &e in &g.lines {
                set.extend(m.lines[e].nodes);
            }
            for &p in &g.panels {
                set.extend(m.panels[p].nodes.as_slice().iter().copied());
            }
            g.nodes = set.into_iter().collect();
        }
    }

    pub fn weight(&mut self, group: usize, node: usize, weight: f64) {
        self.mesh.weights.push(PointWeight {
            node,
            weight,
            group,
        });
    }
}

/// Replicate copy 0 of a single-object mesh at several origins
/// (docs/theory/cages.md#multiple-cages): copy k is copy 0 translated by `origins[k] − origins[0]`;
/// its entities follow copy k−1's; groups are shared.
pub(crate) fn replicate(mesh: &mut Mesh, origins: &[[f64; 3]]) {
    let n0 = mesh.nodes.len();
    let l0 = mesh.lines.len();
    let p0 = mesh.panels.len();
    let w0 = mesh.weights.len();
    let base = Vector3::from(origins[0]);
    for (k, o) in origins.iter().enumerate().skip(1) {
        let shift = Vector3::from(*o) - base;
        let off = k * n0;
        for i in 0..n0 {
            let p = mesh.nodes[i] + shift;
            mesh.nodes.push(p);
            mesh.node_owner.push((mesh.node_owner[i].0, k as u32));
        }
        for e in 0..l0 {
            let mut l = mesh.lines[e];
            l.nodes = l.nodes.map(|n| n + off);
            l.copy = k as u32;
            mesh.lines.push(l);
            let idx = mesh.lines.len() - 1;
            mesh.groups[l.group].lines.push(idx);
        }
        for p in 0..p0 {
            let mut q = mesh.panels[p];
            q.nodes = match q.nodes {
                PanelNodes::Tri(n) => PanelNodes::Tri(n.map(|i| i + off)),
                PanelNodes::Quad(n) => PanelNodes::Quad(n.map(|i| i + off)),
            };
            q.copy = k as u32;
            mesh.panels.push(q);
            let idx = mesh.panels.len() - 1;
            mesh.groups[q.group].panels.push(idx);
        }
        for w in 0..w0 {
            let mut pw = mesh.weights[w];
            pw.node += off;
            mesh.weights.push(pw);
        }
    }
    let copies = origins.len();
    for g in mesh.groups.iter_mut() {
        let base_nodes = g.nodes.clone();
        for k in 1..copies {
            g.nodes.extend(base_nodes.iter().map(|n| n + k * n0));
        }
    }
}

/// Overrides of a line group's section: a `[cage.groups.<group>]` table or the section keys of
/// a `[[line]]` table (docs/theory/fem.md#sections key names).
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SectionOverride {
    /// `diameter` d [m] (also sets the elastic, hydro and volume diameters unless given).
    pub diameter: Option<f64>,
    /// `wall_thickness` of a pipe [m].
    pub wall_thickness: Option<f64>,
    /// `sdr`: standard dimension ratio D/t of a pipe (> 2), instead of `wall_thickness`.
    pub sdr: Option<f64>,
    /// `ea` [N].
    pub ea: Option<f64>,
    /// `youngs_modulus` E [Pa].
    pub youngs_modulus: Option<f64>,
    /// `density` ρ_s [kg/m³].
    pub density: Option<f64>,
    /// `mass_per_length` μ [kg/m].
    pub mass_per_length: Option<f64>,
    /// `hydro_diameter` [m].
    pub hydro_diameter: Option<f64>,
    /// `volume_diameter` [m].
    pub volume_diameter: Option<f64>,
    /// `elastic_diameter` [m].
    pub elastic_diameter: Option<f64>,
    /// `compression_ratio` r_c, 0 ≤ r_c ≤ 1.
    pub compression_ratio: Option<f64>,
    /// `axial_damping` c_a [N·s].
    pub axial_damping: Option<f64>,
    /// `axial_damping_ratio` ζ.
    pub axial_damping_ratio: Option<f64>,
    /// `initial_tension` T0 [N].
    pub initial_tension: Option<f64>,
    /// `seabed` contact on/off.
    pub seabed: Option<bool>,
    /// `contact_diameter` [m].
    pub contact_diameter: Option<f64>,
    /// `material` label.
    pub material: Option<String>,
    /// `ei`: bending stiffness EI [N·m²] (≥ 0; switches bending on unless `bending = false`).
    pub ei: Option<f64>,
    /// `bending`: bending on/off (default: on for pipes and when `ei` is given).
    pub bending: Option<bool>,
    /// `bending_element`: `rod` (default) or `hinge`.
    pub bending_element: Option<BendingElement>,
    /// `poisson_ratio` ν, 0 ≤ ν < 0.5 (default 0.4).
    pub poisson_ratio: Option<f64>,
}

impl SectionOverride {
    /// Apply to `s`, validating every value; `prefix` is the key path used in messages
    /// (e.g. `groups.ropes`).
    pub fn apply(&self, object: &str, prefix: &str, s: &mut Section) -> crate::Result<()> {
        use crate::MeshError;
        let key = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        let pos = |k: &str, v: Option<f64>| -> crate::Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x > 0.0) => Err(MeshError::param(
                    object,
                    &key(k),
                    x,
                    "must be a finite number > 0",
                )),
                _ => Ok(v),
            }
        };
        let nonneg = |k: &str, v: Option<f64>| -> crate::Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x >= 0.0) => Err(MeshError::param(
                    object,
                    &key(k),
                    x,
                    "must be a finite number >= 0",
                )),
                _ => Ok(v),
            }
        };
        if let (Some(t), Some(r)) = (self.wall_thickness, self.sdr) {
            return Err(MeshError::inconsistent(
                object,
                format!(
                    "both `{}` = {t} and `{}` = {r} given; give only one (sdr = diameter / \
                     wall_thickness)",
                    key("wall_thickness"),
                    key("sdr")
                ),
            ));
        }
        if let Some(d) = pos("diameter", self.diameter)? {
            // A pipe keeps its dimension ratio: a new diameter alone scales the wall with it
            // (docs/theory/fem.md#sections).
            if let Some(t) = s.wall_thickness {
                s.wall_thickness = Some(t * d / s.diameter);
            }
            s.diameter = d;
            s.elastic_diameter = d;
            s.hydro_diameter = d;
            s.volume_diameter = d;
        }
        if let Some(t) = pos("wall_thickness", self.wall_thickness)? {
            s.wall_thickness = Some(t);
        }
        if let Some(r) = self.sdr {
            if !(r.is_finite() && r > 2.0) {
                return Err(MeshError::param(
                    object,
                    &key("sdr"),
                    r,
                    "must be > 2 (SDR = diameter / wall_thickness; SDR <= 2 is a wall as thick \
                     as the radius); HDPE pipes are typically SDR 11 to 26",
                ));
            }
            s.wall_thickness = Some(s.diameter / r);
        }
        if let Some(v) = pos("ea", self.ea)? {
            s.ea = Some(v);
        }
        if let Some(v) = pos("youngs_modulus", self.youngs_modulus)? {
            s.youngs_modulus = v;
        }
        if let Some(v) = pos("density", self.density)? {
            s.density = v;
        }
        if let Some(v) = pos("mass_per_length", self.mass_per_length)? {
            s.mass_per_length = Some(v);
        }
        if let Some(v) = pos("hydro_diameter", self.hydro_diameter)? {
            s.hydro_diameter = v;
        }
        if let Some(v) = nonneg("volume_diameter", self.volume_diameter)? {
            s.volume_diameter = v;
        }
        if let Some(v) = pos("elastic_diameter", self.elastic_diameter)? {
            s.elastic_diameter = v;
        }
        if let Some(v) = self.compression_ratio {
            if !(0.0..=1.0).contains(&v) {
                return Err(MeshError::param(
                    object,
                    &key("compression_ratio"),
                    v,
                    "must be in [0, 1]",
                ));
            }
            s.compression_ratio = v;
        }
        if let Some(v) = nonneg("axial_damping", self.axial_damping)? {
            s.axial_damping = Some(v);
        }
        if let Some(v) = nonneg("axial_damping_ratio", self.axial_damping_ratio)? {
            s.axial_damping_ratio = Some(v);
        }
        if let Some(v) = nonneg("initial_tension", self.initial_tension)? {
            s.initial_tension = v;
        }
        if let Some(v) = self.seabed {
            s.seabed = v;
        }
        if let Some(v) = pos("contact_diameter", self.contact_diameter)? {
            s.contact_diameter = Some(v);
        }
        if let Some(m) = &self.material {
            s.material = m.clone();
        }
        if let Some(v) = nonneg("ei", self.ei)? {
            if self.bending == Some(false) {
                return Err(MeshError::param(
                    object,
                    &key("ei"),
                    v,
                    "is given together with `bending = false`; give `ei` to bend with that \
                     stiffness, or `bending = false` alone for no bending",
                ));
            }
            s.ei = Some(v);
        }
        if let Some(v) = self.bending {
            s.bending = Some(v);
        }
        if let Some(v) = self.bending_element {
            s.bending_element = v;
        }
        if let Some(v) = self.poisson_ratio {
            if !(0.0..0.5).contains(&v) {
                return Err(MeshError::param(
                    object,
                    &key("poisson_ratio"),
                    v,
                    "must be in [0, 0.5) (HDPE about 0.4, steel 0.3)",
                ));
            }
            s.poisson_ratio = v;
        }
        check_wall(s, object, &key("wall_thickness"), &key("sdr"))
    }
}

/// A pipe's wall must be thinner than its radius, for the mass (`diameter`) and, unless `ea`
/// is given, for the stiffness (`elastic_diameter`); the error names the wall and the fix.
fn check_wall(s: &Section, object: &str, wall_key: &str, sdr_key: &str) -> crate::Result<()> {
    let Some(t) = s.wall_thickness else {
        return Ok(());
    };
    let mut sizes = vec![("diameter", s.diameter)];
    if s.ea.is_none() {
        sizes.push(("elastic_diameter", s.elastic_diameter));
    }
    for (name, d) in sizes {
        if 2.0 * t >= d {
            return Err(crate::MeshError::param(
                object,
                wall_key,
                t,
                format!(
                    "a pipe wall must be thinner than the radius, {name}/2 = {} m: give a \
                     smaller `{wall_key}` [m], or `{sdr_key}` (wall = diameter/sdr, e.g. 17 for \
                     HDPE pipe)",
                    d / 2.0
                ),
            ));
        }
    }
    Ok(())
}
