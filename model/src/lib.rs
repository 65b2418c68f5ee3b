//! gudsl-model: the GU-DSL language model — lossless syntax tree, typed AST, workspace-wide
//! semantics and editor features, behind one facade ([`AnalysisHost`] / [`Analysis`]). It
//! performs no I/O and knows nothing of editors' protocols, SVG or GPUs.

pub mod analysis;
pub mod ast;
pub mod db;
pub mod format;
pub mod graph;
pub mod hir;
pub mod ide;
pub mod library;
pub mod spelling;
pub mod syntax;
pub mod synth;
pub mod text;

pub use analysis::{Analysis, AnalysisHost, Cancellable, Cancelled, FileId, InvalidEdit, LineColEdit};
pub use syntax::{parse, Parse, SyntaxError, SyntaxErrorCode, SyntaxKind, SyntaxNode, SyntaxToken};
