//! Semantics: the position-independent item tree of each file, the definitions of each
//! namespace, and on top of them one read-only API ([`Semantics`]: names, scopes, types, members,
//! owners, components) that validation, editor features, the graph view and code generation
//! share. Validation rules live apart from it (`validate/`), one family of rules a module.
//!
//! Layers, each using only those below it: `items` → `definitions` → `scope` → `components` →
//! `ty` → `semantics` (+ `instances`, `classify`) → `infer` → `pipeline` → `validate`; `diagnostics` is the vocabulary of
//! problems that `infer` and `validate` report; `uses` (where each name is written) stands
//! beside them, on the syntax only.

pub mod classify;
pub mod components;
pub mod definitions;
pub mod diagnostics;
#[cfg(test)]
pub(crate) mod golden;
pub mod infer;
pub mod instances;
pub mod items;
pub mod pipeline;
pub mod scope;
pub mod semantics;
pub use crate::spelling;
#[cfg(test)]
mod tests;
pub mod ty;
pub mod uses;
pub mod validate;

pub use definitions::{def_map, lookup, DefKind, DefMap, Definition, Fqn};
pub use diagnostics::{Diagnostic, DiagnosticCode, Diagnostics, Related, Severity};
pub use infer::BodyTypes;
pub use items::{item_tree, ItemTree};
pub use scope::Scope;
pub use semantics::Semantics;
pub use ty::Ty;
pub use validate::{check_file, file_diagnostics};
