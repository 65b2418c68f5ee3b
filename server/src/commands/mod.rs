//! One module per `gudsl` subcommand.

pub mod check;
