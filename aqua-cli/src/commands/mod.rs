//! One module per `aqua` subcommand.

pub mod check;
pub mod coeffs;
pub mod collect;
pub mod mesh;
pub mod plot;
pub mod run;
pub mod study;
pub mod sweep;
pub mod waves;
