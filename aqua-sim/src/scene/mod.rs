//! Scene files (TOML), one file per job: the schema of the object sections (`schema.rs`), of
//! the hydrodynamic keys added to mesh tables (`hydro.rs`) and of `[analysis]`
//! (`analysis.rs`); reading a file with errors that name the file, the line, the key and what
//! would be valid (`read.rs`, `sea.rs` for the split of `[sea]`, `slots.rs` for `[[farm.slot]]`); and the list of every key
//! (`keys.rs`).
//!
//! Every key is listed in docs/guide/scene.md (checked by `tests/guide.rs` against
//! [`scene_keys`]). Layout (`x.md#anchor` is a section of `docs/theory/x.md`, `scene.md#anchor`
//! one of docs/guide/scene.md):
//!
//! ```toml
//! name = "reference-cage" # optional; default: the file stem
//! [sea]                   # aqua-env SeaSpec (scene.md#sea); [sea.seabed] is aqua-fem
//!                         # SeabedSettings, split off by the reader (`sea.rs`)
//! [[cage]]                # aqua-mesh CageParams (cages.md#cage-parameters) + net.* hydro keys
//! [[panel]]               # aqua-mesh PanelParams (cages.md#flat-net-panel) + net.* hydro keys
//! [[line]]                # aqua-mesh LineParams (cages.md#single-line) + Morison keys
//! [[mesh]]                # aqua-mesh GmshParams (cages.md#gmsh-import) + net.* hydro keys
//! [[farm]]                # aqua-mesh FarmParams (cages.md#farm-grid); [farm.cage] as [[cage]],
//!                         # [[farm.slot]] per cell (crate::scene::slots)
//! [wake]                  # cage_to_cage (hydrodynamics.md#cage-to-cage-wake)
//! [[group]]               # per element group: section overrides + Morison keys
//! [[point]]               # point bodies on node groups (fem.md#loads)
//! [[buoy]]                # buoys and coupling plates (crate::buoy, farm.md#buoys)
//! [[body]]                # free rigid bodies (crate::body, farm.md#rigid-bodies)
//! [[fix]]                 # extra fixed DOFs (fem.md#boundary-conditions)
//! [[prescribed]]          # prescribed motions (fem.md#boundary-conditions)
//! [analysis]              # static / dynamic settings (scene.md#analysis)
//! ```

mod analysis;
mod hydro;
mod keys;
mod read;
mod schema;
mod sea;
mod slots;

pub use analysis::{AnalysisKind, AnalysisSpec, DEFAULT_DT, DEFAULT_T_END, DynamicSpec, Scheme};
pub use hydro::{LineHydro, NetDrag, NetHydro};
pub use keys::{Key, Keys, scene_keys};
pub use read::{SceneInput, read_scene, read_sea, read_text};
pub use schema::{
    CageSpec, FarmSpec, FixSpec, GroupSpec, LineSpec, Located, MeshSpec, MotionKind, PanelSpec,
    PointSpec, PrescribedSpec, Scene, SceneWake,
};
pub use slots::SlotSpec;

use hydro::NET_HYDRO_KEYS;
use read::{Ctx, line_of, split_keys};
