//! ParaView output people can navigate: a time series of VTK multiblock files
//! (`<stem>.pvd` → `<stem>_NNNNNN.vtm` per step → one `.vtu` per block in `<stem>_NNNNNN/`).
//!
//! # Blocks
//!
//! Every object of the mesh (a cage, a panel, a line, an imported mesh; every copy of a
//! multi-origin object separately) is one top-level block, and holds up to three datasets named
//! after their kind:
//!
//! * `lines`: its line elements as `VTK_LINE` (twines, ropes, rings, chains), with the cell
//!   arrays of the caller's `line` arrays (tension, …);
//! * `panels`: its net panels as `VTK_TRIANGLE`/`VTK_QUAD` (screen-load elements: they carry no
//!   tension), with the caller's `panel` arrays;
//! * `points`: every node the object owns, once, as `VTK_VERTEX`; the point-data of all
//!   `points` datasets together is the point data of the whole model, node by node.
//!
//! A block is named after its object in the characters ParaView keeps in its hierarchy (ASCII
//! letters, digits and `_`; ParaView 5.11 silently drops every other character, so a block named
//! `farm/cage_r1c1` would be selected only as `/Root/farmcage_r1c1`): every other character of
//! the object's name becomes `_` (`farm/cage_r1c1` → `farm_cage_r1c1`, `m-east` → `m_east`),
//! copy k of a multi-origin object is `name_k` (the scene's `name#k`), a name starting with a
//! digit gets a leading `_` (as ParaView would), and a name that two objects would share gets
//! `_2`, `_3`, … on the later ones. [`NameTables::block_names`] lists the block paths and
//! [`NameTables::block_objects`] the object each one belongs to.
//!
//! So ParaView's *Multiblock Inspector* lists `cage0` → `lines`, `panels`, `points`, `m_east` →
//! `lines`, `points`, and each can be switched on and off by name; selectors are
//! `/Root/cage0/lines`, `/Root/farm_cage_r1c1`, `//panels`, …
//!
//! `lines` and `panels` datasets hold the nodes their cells use (a fairlead shared with a cage
//! appears in both objects' datasets); the `points` datasets partition the nodes. The node
//! index in the whole mesh is the point array `node_id`; the element/panel index is the cell
//! array `element_id`/`panel_id`.
//!
//! # Points
//!
//! Point coordinates are the positions passed to [`MultiblockSeries::write_step`] (for a run,
//! the deformed positions x = X + `displacement`). The undeformed geometry X is written once, by
//! [`MultiblockSeries::write_reference`], as `<stem>_reference.vtm` with the same blocks in the
//! same order and the same points. *Warp By Vector* (`displacement`, scale S − 1) applied to the
//! series gives X + S·`displacement` at every time step: the deformation scaled by S.
//!
//! # Field data (every dataset)
//!
//! `TimeValue` (the step time [s]) only: numbers, which every VTK reader (meshio included)
//! reads. The name tables — `object_names` (index = `object_id`), `group_names`
//! (`object/group`, index = `group_id`), `role_names` (index = `role_id`), `block_names`,
//! `block_objects` ([`NameTables`]) — are the caller's to write (`aqua run` puts them in
//! `run.json`); the block names themselves are in the `.vtm` hierarchy.
//!
//! # Files
//!
//! Per step: one directory, its block files written in place (each in one `write`), then the
//! `.vtm` written to a temporary name and renamed, then one line in the `.pvd`: the new
//! `<DataSet>` and the closing tags written in one `write` over the old closing tags, so a
//! long run never rewrites the `.pvd`. The parts of a block file that are the same every
//! step (ids, names, sections, connectivity) are rendered once. Data arrays are inline
//! base64 (`format="binary"`), so every file stays well-formed XML.
//!
//! Nothing is fsynced. What holds if the process stops at any moment (an error, Ctrl-C, a
//! kill): every step the `.pvd` lists is complete, and every `<stem>_NNNNNN.vtm` on disk is
//! complete and listed, except that a kill during the one small `.pvd` write can cut that
//! line. A failed step removes what it had written. Against an operating-system crash or a
//! power cut nothing is promised (the page cache may not have reached the disk).

mod arrays;
mod block;
mod layout;
mod multiblock;
mod pvd;
mod series;
mod xml;

pub use arrays::{ArrayValues, BUILTIN, BlockArray, StepArrays};
pub use layout::{BlockKind, BlockLayout, BlockSpec, NameTables, paraview_block_name};
pub use multiblock::write_geometry;
pub use series::MultiblockSeries;
