//! One module per `aqua` subcommand.

pub mod waves;
