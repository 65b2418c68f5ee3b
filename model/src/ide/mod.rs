//! Editor features computed on the model, in byte offsets and model types only (the server
//! converts them to LSP): document outline, folding, go to definition and hover.

mod folding;
mod navigation;
mod symbols;

pub use folding::{folding_ranges, Fold, FoldKind};
pub use navigation::{goto_definition, hover, NavigationTarget};
pub use symbols::{document_symbols, Symbol, SymbolKind};
