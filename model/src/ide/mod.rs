//! Editor features computed on the model, in byte offsets and model types only (the server
//! converts them to LSP): outline, folding, navigation, references and rename, completion,
//! selection ranges, workspace symbols, semantic tokens, graph edits as text edits.

mod completion;
mod fixes;
mod folding;
mod graph_edit;
mod hints;
mod navigation;
mod parameters;
mod references;
mod structure;
mod symbols;
#[cfg(test)]
mod test_fixture;

pub use completion::{completions, CompletionItem, CompletionKind, Completions};
pub use fixes::{quick_fixes, QuickFix};
pub use folding::{folding_ranges, Fold, FoldKind};
pub use graph_edit::{graph_edit, property, GraphEditError, GraphOp, NewKind, Properties};
pub use hints::{inlay_hints, signature_help, InlayHint, SignatureHelp};
pub use navigation::{goto_definition, goto_type_definition, hover, NavigationTarget};
pub use parameters::{parameter_edit, ParameterEdit};
pub use references::{find_references, prepare_rename, rename, FileRange, RenameError};
pub use structure::{
    selection_ranges, semantic_tokens, workspace_symbols, HighlightedToken, TokenClass, WorkspaceSymbol,
    WorkspaceSymbolKind,
};
pub use symbols::{document_symbols, Symbol, SymbolKind};
