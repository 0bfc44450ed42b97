//! The structural model: nodes, cable elements, point bodies, supports, seabed. It is built,
//! and every input validated, by [`ModelBuilder`] (`builder.rs`).

use crate::bending::Hinge;
use crate::error::{FemError, Result, invalid};
use crate::friction::SeabedFriction;
use crate::motion::Motion;
use crate::net_triangle::{NetTriangle, NetTriangleGroup, NetTriangleTwines};
use crate::rigid_body::{Link, RigidBody};
use crate::rod::{RodEdge, RodVertex};
use crate::seabed::SeabedSettings;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

pub use crate::builder::ModelBuilder;

/// Default gravitational acceleration [m/s²] (standard gravity, the one value of
/// `aqua-constants`; a scene passes its sea's g).
pub const DEFAULT_GRAVITY: f64 = aqua_constants::STANDARD_GRAVITY;
/// Default sea-water density [kg/m³] (`aqua-constants`).
pub const DEFAULT_WATER_DENSITY: f64 = aqua_constants::SEA_WATER_DENSITY;
/// Default compression ratio r_c of cable elements.
pub const DEFAULT_COMPRESSION_RATIO: f64 = 0.0;

pub use crate::seabed::DEFAULT_BED_DAMPING_DEPTH;

fn default_damping_depth() -> f64 {
    DEFAULT_BED_DAMPING_DEPTH
}

/// Flat seabed at z = −depth with a penalty contact law (MoorDyn's `kBot`/`cBot`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Seabed {
    /// Water depth [m] (> 0): the seabed plane is z = −depth.
    pub depth: f64,
    /// Normal stiffness k_b per unit contact area [Pa/m]. Default: [`SeabedSettings`]'s.
    pub stiffness: f64,
    /// Normal damping c_b per unit contact area [Pa·s/m]. Default: [`SeabedSettings`]'s.
    pub damping: f64,
    /// Penetration δ_c over which the damping ramps in linearly from zero [m] (> 0). Default:
    /// [`SeabedSettings`]'s. Keeps the contact force continuous at touchdown (docs/theory/fem.md#seabed-contact).
    #[serde(default = "default_damping_depth")]
    pub damping_depth: f64,
    /// Regularised Coulomb friction (docs/theory/fem.md#seabed-friction). Default off.
    #[serde(default)]
    pub friction: SeabedFriction,
}

impl Seabed {
    /// Seabed at depth [m] with the default constants of [`SeabedSettings`] (no friction).
    pub fn new(depth: f64) -> Self {
        SeabedSettings::default().seabed(depth)
    }

    /// Sets the friction.
    pub fn with_friction(mut self, friction: SeabedFriction) -> Self {
        self.friction = friction;
        self
    }
}

/// What the environment passes to the structure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Environment {
    /// Gravitational acceleration g [m/s²] (≥ 0).
    pub gravity: f64,
    /// Water density ρ_w [kg/m³] (> 0); kept for load providers, the FEM itself adds no water load.
    pub water_density: f64,
    /// Seabed, if any.
    pub seabed: Option<Seabed>,
}

impl Default for Environment {
    fn default() -> Self {
        Self {
            gravity: DEFAULT_GRAVITY,
            water_density: DEFAULT_WATER_DENSITY,
            seabed: None,
        }
    }
}

/// Axial damping of a cable section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum AxialDamping {
    /// No axial damping.
    #[default]
    None,
    /// Axial damping coefficient c_a [N·s] (T = s·EA·ε + d(ε)·c_a·ε̇,
    /// docs/theory/fem.md#cable-element).
    Coefficient(f64),
    /// Ratio ζ of critical: c_a = ζ·L0·√(EA·μ) per element.
    Ratio(f64),
}

/// Cross-section properties of an element group.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CableSection {
    /// Axial stiffness EA [N] (> 0).
    pub ea: f64,
    /// Mass per unstretched length μ [kg/m] (> 0).
    pub mass_per_length: f64,
    /// Compression ratio r_c ∈ [0, 1]: stiffness factor when ε ≤ 0. Default 0 (tension-only:
    /// a slack cable carries no force).
    pub compression_ratio: f64,
    /// Axial damping.
    pub axial_damping: AxialDamping,
    /// Seabed contact diameter d_c [m]; `None` disables seabed contact for the group.
    pub contact_diameter: Option<f64>,
}

impl CableSection {
    /// Section with EA [N] and μ [kg/m], default compression ratio, no damping, no contact.
    pub fn new(ea: f64, mass_per_length: f64) -> Self {
        Self {
            ea,
            mass_per_length,
            compression_ratio: DEFAULT_COMPRESSION_RATIO,
            axial_damping: AxialDamping::None,
            contact_diameter: None,
        }
    }

    /// Sets the seabed contact diameter [m].
    pub fn with_contact(mut self, diameter: f64) -> Self {
        self.contact_diameter = Some(diameter);
        self
    }

    /// Sets the compression ratio r_c.
    pub fn with_compression_ratio(mut self, rc: f64) -> Self {
        self.compression_ratio = rc;
        self
    }

    /// Sets the axial damping.
    pub fn with_axial_damping(mut self, d: AxialDamping) -> Self {
        self.axial_damping = d;
        self
    }

    pub(crate) fn validate(&self, group: &str) -> Result<()> {
        if !(self.ea.is_finite() && self.ea > 0.0) {
            return Err(invalid(format!("group '{group}' ea [N]"), self.ea, "> 0"));
        }
        if !(self.mass_per_length.is_finite() && self.mass_per_length > 0.0) {
            return Err(invalid(
                format!("group '{group}' mass_per_length [kg/m]"),
                self.mass_per_length,
                "> 0",
            ));
        }
        if !(0.0..=1.0).contains(&self.compression_ratio) {
            return Err(invalid(
                format!("group '{group}' compression_ratio"),
                self.compression_ratio,
                "0 <= r_c <= 1",
            ));
        }
        match self.axial_damping {
            AxialDamping::None => {}
            AxialDamping::Coefficient(c) if c.is_finite() && c >= 0.0 => {}
            AxialDamping::Ratio(z) if z.is_finite() && z >= 0.0 => {}
            AxialDamping::Coefficient(c) => {
                return Err(invalid(
                    format!("group '{group}' axial_damping [N s]"),
                    c,
                    ">= 0",
                ));
            }
            AxialDamping::Ratio(z) => {
                return Err(invalid(
                    format!("group '{group}' axial_damping_ratio"),
                    z,
                    ">= 0",
                ));
            }
        }
        if let Some(d) = self.contact_diameter
            && !(d.is_finite() && d > 0.0)
        {
            return Err(invalid(
                format!("group '{group}' contact_diameter [m]"),
                d,
                "> 0",
            ));
        }
        Ok(())
    }
}

/// How the unstretched length of an element is given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum UnstretchedLength {
    /// L0 [m] directly (> 0).
    Given(f64),
    /// From the as-built length and an initial tension T0 [N]: L0 = l/(1 + T0/EA).
    AsBuilt {
        /// Initial tension T0 [N] (> −EA).
        initial_tension: f64,
    },
}

/// A 2-node cable element (resolved properties).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cable {
    /// First node.
    pub a: usize,
    /// Second node.
    pub b: usize,
    /// Unstretched length L0 [m].
    pub l0: f64,
    /// Axial stiffness EA [N].
    pub ea: f64,
    /// Compression ratio r_c.
    pub rc: f64,
    /// Axial damping coefficient c_a [N·s].
    pub ca: f64,
    /// Mass per unstretched length μ [kg/m].
    pub mu: f64,
    /// Group index.
    pub group: usize,
    /// Seabed contact diameter [m] (0 = no contact).
    pub contact_diameter: f64,
}

/// A point body on a node: mass, constant force and optional seabed stiffness.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PointBody {
    /// Node index.
    pub node: usize,
    /// Mass m [kg] (≥ 0); its weight −m·g ẑ is applied.
    pub mass: f64,
    /// Constant force [N].
    pub force: [f64; 3],
    /// Seabed penalty stiffness [N/m] (≥ 0, 0 = none).
    pub seabed_stiffness: f64,
}

/// Which translational DOFs of a node are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Dofs {
    /// x held.
    pub x: bool,
    /// y held.
    pub y: bool,
    /// z held.
    pub z: bool,
}

impl Dofs {
    /// All three DOFs.
    pub const ALL: Dofs = Dofs {
        x: true,
        y: true,
        z: true,
    };
    /// As an array.
    pub fn as_array(self) -> [bool; 3] {
        [self.x, self.y, self.z]
    }
}

/// Support condition of a node.
#[derive(Debug, Clone, PartialEq)]
pub enum Support {
    /// No support.
    Free,
    /// Held at the as-built position in the given DOFs.
    Fixed(Dofs),
    /// All DOFs follow x = X + d(t) (index into the model's motions).
    Prescribed(usize),
}

/// Named element group.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Name.
    pub name: String,
    /// Section.
    pub section: CableSection,
    /// Elements of the group.
    pub elements: Vec<usize>,
}

/// Handle of an element group.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GroupId(pub usize);

/// Section of a rod (docs/theory/fem.md#rod).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodSection {
    /// Bending stiffness EI [N·m²].
    pub ei: f64,
    /// Torsional stiffness GJ [N·m²].
    pub gj: f64,
    /// Spin inertia per unit length, ∫ρ·r² dA [kg·m] (the mass moment of inertia about the
    /// pipe's axis per metre).
    pub spin_inertia: f64,
}

impl RodSection {
    pub(crate) fn validate(&self, what: &str) -> Result<()> {
        for (key, v, ok) in [
            ("bending stiffness EI [N m^2]", self.ei, self.ei > 0.0),
            ("torsional stiffness GJ [N m^2]", self.gj, self.gj > 0.0),
            (
                "spin inertia [kg m]",
                self.spin_inertia,
                self.spin_inertia >= 0.0,
            ),
        ] {
            if !(v.is_finite() && ok) {
                return Err(invalid(
                    format!("{what} {key}"),
                    v,
                    if key.starts_with("spin") {
                        ">= 0"
                    } else {
                        "> 0"
                    },
                ));
            }
        }
        Ok(())
    }
}

/// The rods of a model: vertices, edges, their auxiliary nodes.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rods {
    pub n_rods: usize,
    pub vertices: Vec<RodVertex>,
    pub edges: Vec<RodEdge>,
    /// Twist carrier and its spin inertia [kg·m²].
    pub carrier_inertia: Vec<(usize, f64)>,
    /// Held ghost nodes beyond clamped ends.
    pub holders: Vec<usize>,
    /// Per node: a twist carrier or a ghost node (filled at build).
    pub auxiliary: Vec<bool>,
}

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
}

/// A validated structural model (immutable; solvers borrow it).
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) env: Environment,
    pub(crate) nodes: Vec<[f64; 3]>,
    pub(crate) elements: Vec<Cable>,
    pub(crate) groups: Vec<Group>,
    pub(crate) group_index: HashMap<String, usize>,
    pub(crate) points: Vec<PointBody>,
    pub(crate) supports: Vec<Support>,
    pub(crate) motions: Vec<Motion>,
    pub(crate) hinges: Vec<Hinge>,
    pub(crate) rods: Rods,
    pub(crate) net_triangles: Vec<NetTriangle>,
    pub(crate) net_groups: Vec<NetTriangleGroup>,
    /// Free rigid bodies (docs/theory/fem.md#rigid-bodies).
    pub(crate) bodies: Vec<RigidBody>,
    /// The rigid links of every body's held points.
    pub(crate) links: Vec<Link>,
    /// Per node: the body whose rotation carrier it is (filled at build).
    pub(crate) rotation_of: Vec<Option<usize>>,
    /// Lumped structural mass per node [kg] (twist carriers: spin inertia [kg·m²]; rotation
    /// carriers: 0, their inertia is a full block, docs/theory/fem.md#rigid-bodies).
    pub(crate) lumped_mass: Vec<f64>,
    /// Nodal weight vector [N].
    pub(crate) weight: Vec<[f64; 3]>,
    /// Constant point forces per node [N].
    pub(crate) point_force: Vec<[f64; 3]>,
    /// Σ d_c·L0/2 of contact elements per node [m²].
    pub(crate) bed_coef: Vec<f64>,
    /// Point-body seabed stiffness per node [N/m].
    pub(crate) bed_point: Vec<f64>,
    /// Point-body mass per node [kg].
    pub(crate) point_mass: Vec<f64>,
    pub(crate) mean_length: f64,
    /// Part of each node (a prefix of the nodes) for the block solve, if partitioned.
    pub(crate) partition: Option<Vec<usize>>,
}

impl Model {
    /// Number of nodes whose motion is prescribed (fairleads driven by a motion).
    pub fn n_prescribed_motions(&self) -> usize {
        self.motions.len()
    }

    /// Environment (g, ρ_w, seabed).
    pub fn environment(&self) -> &Environment {
        &self.env
    }
    /// The part of each node given to [`Model::set_partition`] (a prefix of the nodes), if
    /// any.
    pub fn partition(&self) -> Option<&[usize]> {
        self.partition.as_deref()
    }
    /// Partitions the nodes for the block solve of the linear systems, or removes the
    /// partition (`None`): `part_of_node[i]` is node i's part (any numbers); nodes beyond the
    /// list (e.g. a rod's twist carriers) join the part of a neighbour. The LU path then
    /// eliminates each part's interior apart, in parallel, and the DOFs where parts touch
    /// through their Schur complement (docs/theory/fem.md#block-solve); a partition changes
    /// only the round-off of a solution.
    pub fn set_partition(&mut self, part_of_node: Option<Vec<usize>>) -> Result<()> {
        if let Some(p) = &part_of_node
            && p.len() > self.nodes.len()
        {
            return Err(FemError::InvalidModel(format!(
                "the partition lists {} nodes; the model has {}",
                p.len(),
                self.nodes.len()
            )));
        }
        self.partition = part_of_node;
        Ok(())
    }
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// As-built node positions X [m].
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }
    /// Cable elements.
    pub fn elements(&self) -> &[Cable] {
        &self.elements
    }
    /// Bending hinges.
    pub fn hinges(&self) -> &[Hinge] {
        &self.hinges
    }
    /// Rod vertices (bending and torsion, docs/theory/fem.md#rod).
    pub fn rod_vertices(&self) -> &[RodVertex] {
        &self.rods.vertices
    }
    /// Rod edges, each with its twist carrier and cable element.
    pub fn rod_edges(&self) -> &[RodEdge] {
        &self.rods.edges
    }
    /// Number of rods.
    pub fn n_rods(&self) -> usize {
        self.rods.n_rods
    }
    /// Whether node `i` is a rod's twist carrier (its first coordinate is a twist angle [rad];
    /// its held coordinates hold nothing of the structure).
    pub fn is_twist_carrier(&self, i: usize) -> bool {
        self.rods.auxiliary.get(i).copied().unwrap_or(false) && !self.rods.holders.contains(&i)
    }
    /// Whether node `i` is a rigid body's rotation carrier (its three coordinates are the
    /// body's accumulated rotation vector ψ [rad], not a position;
    /// docs/theory/fem.md#rigid-bodies).
    pub fn is_rotation_carrier(&self, i: usize) -> bool {
        self.rotation_of.get(i).is_some_and(|b| b.is_some())
    }
    /// Whether node `i` is not a point of the structure: a rod's twist carrier (its first
    /// coordinate is a twist angle [rad]), a held ghost node of a clamped rod end, or a rigid
    /// body's rotation carrier (its coordinates are a rotation vector [rad]).
    pub fn is_auxiliary(&self, i: usize) -> bool {
        self.rods.auxiliary.get(i).copied().unwrap_or(false) || self.is_rotation_carrier(i)
    }
    /// Free rigid bodies (docs/theory/fem.md#rigid-bodies).
    pub fn rigid_bodies(&self) -> &[RigidBody] {
        &self.bodies
    }
    /// Net triangles (docs/theory/fem.md#net-triangle).
    pub fn net_triangles(&self) -> &[NetTriangle] {
        &self.net_triangles
    }
    /// Net triangle groups.
    pub fn net_triangle_groups(&self) -> &[NetTriangleGroup] {
        &self.net_groups
    }
    /// The twines of net triangle `i` at node positions `x` (all nodes, e.g. `State::x`):
    /// twine vectors, tension of one twine of each family (static law) and opening angle.
    pub fn net_triangle_twines(&self, i: usize, x: &[[f64; 3]]) -> NetTriangleTwines {
        self.net_triangles[i].twines(x)
    }
    /// The largest axial stiffness EA of a cable or of one twine of a net triangle [N].
    pub(crate) fn max_axial_stiffness(&self) -> f64 {
        let cables = self.elements.iter().map(|e| e.ea);
        let twines = self.net_triangles.iter().map(|t| t.twine.ea);
        cables.chain(twines).fold(0.0, f64::max)
    }
    /// Groups.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }
    /// Element indices of a named group.
    pub fn group_elements(&self, name: &str) -> Option<&[usize]> {
        self.group_index
            .get(name)
            .map(|&g| self.groups[g].elements.as_slice())
    }
    /// Point bodies.
    pub fn point_bodies(&self) -> &[PointBody] {
        &self.points
    }
    /// Support of each node.
    pub fn supports(&self) -> &[Support] {
        &self.supports
    }
    /// Lumped structural mass per node [kg] (elements + point bodies).
    pub fn lumped_mass(&self) -> &[f64] {
        &self.lumped_mass
    }
    /// Point-body mass on node i [kg].
    pub(crate) fn point_mass_at(&self, i: usize) -> f64 {
        self.point_mass[i]
    }
    /// Mean unstretched length of the cables and the net triangles' bars [m] (L_ref).
    pub fn mean_element_length(&self) -> f64 {
        self.mean_length
    }
    /// Whether DOF k of node i is constrained (fixed or prescribed).
    pub fn is_constrained(&self, node: usize, k: usize) -> bool {
        match &self.supports[node] {
            Support::Free => false,
            Support::Fixed(d) => d.as_array()[k],
            Support::Prescribed(_) => true,
        }
    }

    /// Position, velocity and acceleration of node `i` if it is prescribed, at time t.
    pub(crate) fn prescribed(
        &self,
        i: usize,
        t: f64,
        scale: f64,
    ) -> Option<([f64; 3], [f64; 3], [f64; 3])> {
        match &self.supports[i] {
            Support::Prescribed(m) => {
                let (d, v, a) = self.motions[*m].eval(t);
                let x0 = self.nodes[i];
                Some((
                    [
                        x0[0] + scale * d[0],
                        x0[1] + scale * d[1],
                        x0[2] + scale * d[2],
                    ],
                    v.map(|c| c * scale),
                    a.map(|c| c * scale),
                ))
            }
            _ => None,
        }
    }

    /// Sets constrained DOFs of (x, v, a) to their values at time t (prescribed offsets scaled
    /// by `scale`, used by load continuation).
    pub(crate) fn apply_constraints(
        &self,
        t: f64,
        scale: f64,
        x: &mut [[f64; 3]],
        v: &mut [[f64; 3]],
        a: &mut [[f64; 3]],
    ) {
        for i in 0..self.nodes.len() {
            match &self.supports[i] {
                Support::Free => {}
                Support::Fixed(d) => {
                    for (k, held) in d.as_array().into_iter().enumerate() {
                        if held {
                            x[i][k] = self.nodes[i][k];
                            v[i][k] = 0.0;
                            a[i][k] = 0.0;
                        }
                    }
                }
                Support::Prescribed(_) => {
                    if let Some((p, vel, acc)) = self.prescribed(i, t, scale) {
                        x[i] = p;
                        v[i] = vel;
                        a[i] = acc;
                    }
                }
            }
        }
    }
}
