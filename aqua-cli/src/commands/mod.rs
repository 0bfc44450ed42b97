//! One module per `aqua` subcommand.

pub mod mesh;
pub mod waves;
