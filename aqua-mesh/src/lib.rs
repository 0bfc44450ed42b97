//! aqua-mesh: the geometry of aquaculture structures.
//!
//! * Parametric cage builders **CCT, CCS, CSM, SSM** ([`CageParams`],
//!   docs/theory/cages.md#cage-types to #multiple-cages), a flat net panel builder
//!   ([`PanelParams`], #flat-net-panel), a single-line builder ([`LineParams`], #single-line;
//!   one section or [`LineSegment`]s), the node of a free buoy ([`buoy_node`]) and a farm
//!   builder: cages on a square mooring grid with frame, bridles, buoys and anchor lines
//!   ([`FarmParams`], #farm-grid).
//! * gmsh import of MSH 4.1 (ASCII and binary, through `mshio`) and MSH 2.2 ASCII ([`io::gmsh`]).
//! * VTK export ([`io::vtm`]): multiblock files with one named block per object and kind, as the
//!   geometry of a mesh ([`write_geometry`]) or a run's time series ([`MultiblockSeries`]).
//!
//! # Governing relations
//!
//! Discretisation (round half away from zero, never truncate), for circumference C, side depth
//! H, element length el, bottom radius R_b (square: side a = C/4):
//!
//! ```text
//! NT = round(C/el)            (square: NT = 4·round(a/el))
//! NN = round(H/el)
//! BN = round(R_b/(√2·el))     (square: round(a/(√2·el)))
//! net node (i, ℓ) = origin + ρ_ℓ·u_i + z_ℓ·ẑ,   id = i·(NN+BN) + ℓ
//! ```
//!
//! Mesh grouping (docs/theory/cages.md#mesh-grouping, docs/theory/fem.md#sections): one numerical
//! twine of mean as-built length L̄ stands for λ = L̄ / l_p physical twines of diameter dw0 and bar
//! length l_p, with
//!
//! ```text
//! dws = dwe = √λ · dw0      (structural/elastic: mass, volume, EA)
//! dwh = λ · dw0             (hydrodynamic: projected area)
//! ```
//!
//! Point weights W [N] (sinkers W = w·C/NT each, centre weight, tip weight) become point bodies
//! of mass W/g and zero volume downstream.
//!
//! # Data model
//!
//! A [`Mesh`] holds node positions, 2-node [`LineElement`]s, [`Panel`]s (triangles and quads in
//! cyclic order, normal out of the cage), [`Group`]s (name, [`Role`], members, [`Section`]),
//! [`PointWeight`]s and one [`Object`] per builder call (with its [`NetGrouping`]). All units SI,
//! z up, z = 0 at the still-water level.
//!
//! # Layers
//!
//! Each layer uses only those above it:
//!
//! 1. [`error`], [`limits`];
//! 2. [`section`] (sections and materials) and [`section_override`] (their scene keys);
//! 3. [`model`]: the mesh, its elements, groups, roles and objects, with the builders'
//!    descriptions of what they built ([`CageType`], [`CageCounts`], [`NetGrouping`]);
//! 4. the builders ([`cage`], [`panel`], [`line`](mod@line), [`buoy`], [`farm`], with [`net`],
//!    [`net_triangle`] and [`collar`]), adding to a mesh through an internal mesh builder;
//! 5. [`summary`] (reports) and [`io`] (gmsh import, VTK export);
//! 6. [`request`]: one builder call from flat keys, as `aqua mesh` takes them.

pub mod body;
pub mod buoy;
pub mod cage;
pub mod collar;
pub mod error;
pub mod farm;
pub mod io;
pub mod limits;
pub mod line;
mod mesh_builder;
pub mod model;
pub mod net;
pub mod net_triangle;
pub mod panel;
pub mod request;
pub mod section;
pub mod section_override;
pub mod summary;
pub mod summary_text;

pub use body::{BoxHull, HULL_GROUP, body_mesh};
pub use buoy::{BUOY_GROUP, buoy_node};
pub use cage::{CageParams, ResolvedCage};
pub use collar::{Collar, CollarParams};
pub use error::{FilePos, MeshError, Result};
pub use farm::{FarmCounts, FarmMesh, FarmParams};
pub use io::gmsh::{GmshParams, import_gmsh, read_msh};
pub use io::vtm::{
    BlockArray, BlockKind, BlockLayout, MultiblockSeries, NameTables, StepArrays, write_geometry,
};
pub use limits::MAX_LENGTH;
pub use line::{Fairlead, INITIAL_STRETCH, LineParams, LineSegment, LineShape};
pub use model::{
    CageCounts, CageType, Group, LineElement, Mesh, MeshOrientation, NetElement, NetGrouping,
    Object, ObjectDetail, ObjectKind, Panel, PanelNodes, PointWeight, Role,
};
pub use net::{NetParams, NetResolved, TwineAreas};
pub use panel::{PanelFixed, PanelParams};
pub use request::{Builder, MeshRequest, RequestError};
pub use section::{BendingElement, DEFAULT_POISSON_RATIO, Section, TENSION_ONLY};
pub use section_override::SectionOverride;
pub use summary::{GroupSummary, MeshSummary, ObjectSummary};

/// Build several cages, panels or lines into one mesh (objects appended in order).
pub fn merge(meshes: impl IntoIterator<Item = Mesh>) -> Mesh {
    let mut out = Mesh::default();
    for m in meshes {
        out.append(m);
    }
    out
}
