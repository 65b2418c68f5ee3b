//! One module per `gudsl` subcommand.

pub mod check;
pub mod fmt;
