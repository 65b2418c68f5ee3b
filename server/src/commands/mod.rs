//! One module per `gudsl` subcommand.

pub mod check;
pub mod fmt;
pub mod render;
pub mod wgsl;
