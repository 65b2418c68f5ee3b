//! gudsl-model: the GU-DSL language model — lossless syntax tree, typed AST and (later)
//! workspace-wide semantics. It performs no I/O and knows nothing of editors, SVG or GPUs.

pub mod ast;
pub mod db;
pub mod format;
pub mod graph;
pub mod hir;
pub mod ide;
pub mod syntax;
pub mod synth;
pub mod text;

pub use syntax::{parse, Parse, SyntaxError, SyntaxErrorCode, SyntaxKind, SyntaxNode, SyntaxToken};
