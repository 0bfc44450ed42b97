//! The `[sea]` table of a scene (docs/guide/scene.md#sea), one file per job: the schema
//! (`schema.rs`), the checks of its keys (`validate.rs`), the construction of the [`Sea`]
//! (`build.rs`) and the printed summary (`summary.rs`).
//!
//! [`Sea`]: crate::Sea

mod build;
mod schema;
mod summary;
mod validate;

pub use build::BuildOptions;
pub use schema::{
    CurrentKind, CurrentSpec, DepthValue, GammaValue, SeaSpec, SpectrumShape, SpectrumSpec,
    WaterSpec, WaveKind, WavesSpec,
};
pub use summary::{IrregularSummary, RegularWaveSummary, SeaSummary};
