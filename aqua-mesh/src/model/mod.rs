//! The data model of a mesh: nodes, elements, panels, groups by role, point weights and the
//! objects that own them.
//!
//! The model depends on sections ([`crate::section`]) and on nothing that builds meshes: the
//! builders (cages, panels, lines, farms, gmsh) fill its descriptions of what they built
//! ([`ObjectKind`], [`CageCounts`], [`NetGrouping`]).

mod element;
mod mesh;
mod net_grouping;
mod object;
mod role;

pub use element::{Group, LineElement, Panel, PanelNodes, PointWeight};
pub use mesh::Mesh;
pub use net_grouping::{MeshOrientation, NetElement, NetGrouping};
pub use object::{CageCounts, CageType, Object, ObjectDetail, ObjectKind};
pub use role::Role;
