//! Semantics: the position-independent item tree of each file, the workspace-wide definition
//! map, name resolution and validation, all as salsa queries over [`crate::db`].

pub mod check;
pub mod components;
pub mod definitions;
pub mod diagnostics;
#[cfg(test)]
mod golden;
pub mod infer;
pub mod items;
#[cfg(test)]
mod tests;
pub mod ty;

pub use definitions::{def_map, lookup, DefKind, DefMap, Definition, Fqn};
pub use diagnostics::{file_diagnostics, Diagnostic, DiagnosticCode, Severity};
pub use items::{item_tree, ItemTree};
