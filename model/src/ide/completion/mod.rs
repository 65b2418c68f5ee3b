//! Completion that knows where the cursor is: node names after `=>`, qualified names after a
//! `.`, types in type positions, the owner class's members and the locals inside bodies,
//! interfaces after `:` in ports, fields in `instantiates X (`, and keyword snippets for the
//! constructs valid at that level. Shaped as rust-analyzer's `ide-completion`: a context says
//! where the cursor is (`context.rs`), providers each propose what fits one kind of place and
//! the first that applies answers (`providers.rs`); the names they list are `names.rs`'s, the
//! snippets of each declaration level `snippets.rs`'s.

mod context;
mod names;
mod providers;
mod snippets;

use crate::{
    db::{Db, SourceFile, Workspace},
    syntax::TextSize,
};

/// What a completion item is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum CompletionKind {
    Keyword,
    Snippet,
    Type,
    Namespace,
    Node,
    Field,
    Method,
    Variable,
    Interface,
    EnumValue,
}

/// One proposal.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct CompletionItem {
    pub label: String,
    pub kind: CompletionKind,
    pub detail: Option<String>,
    /// Text to insert in LSP snippet syntax (`$1`, `${1:name}`), when it differs from the label.
    pub snippet: Option<String>,
    /// Declared outside what the cursor's scope sees (a type of another diagram that resolves
    /// by its unique simple name): listed after the names in scope.
    pub far: bool,
}

/// The proposals at a position; `incomplete` when a long list was cut to what is typed so far
/// (the editor asks again as the user types on).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Completions {
    pub items: Vec<CompletionItem>,
    pub incomplete: bool,
}

pub(super) fn item(label: impl Into<String>, kind: CompletionKind, detail: Option<String>) -> CompletionItem {
    CompletionItem { label: label.into(), kind, detail, snippet: None, far: false }
}

pub(super) fn snippet(label: &str, body: &str, detail: &str) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: CompletionKind::Snippet,
        detail: Some(detail.to_string()),
        snippet: Some(body.to_string()),
        far: false,
    }
}

/// The proposals at `offset`: those of the first provider that applies there.
pub fn completions(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Completions {
    let ctx = context::Ctx::new(db, workspace, file, offset);
    providers::ALL.iter().find_map(|provide| provide(&ctx)).unwrap_or_else(|| snippets::at_level(&ctx))
}

/// The proposals sorted, each label of a kind once.
pub(super) fn finish(mut items: Vec<CompletionItem>) -> Completions {
    items.sort();
    items.dedup_by(|a, b| a.label == b.label && a.kind == b.kind);
    Completions { items, incomplete: false }
}

#[cfg(test)]
mod tests;
