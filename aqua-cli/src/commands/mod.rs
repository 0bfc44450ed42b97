//! One module per `aqua` subcommand.

pub mod check;
pub mod coeffs;
pub mod mesh;
pub mod run;
pub mod waves;
