//! The facade every client of the model uses (rust-analyzer's `ide::AnalysisHost` / `Analysis`):
//! an [`AnalysisHost`] owns the database and applies changes (new files, new texts, editor
//! edits, the set of files analysed together); an [`Analysis`] is a snapshot that answers
//! queries. A change applied to the host cancels the work of older snapshots: their queries
//! return `Err(Cancelled)` instead of finishing on stale text.
//!
//! Everything is in byte offsets and model types; the language server converts at its edge.

use std::panic::AssertUnwindSafe;

use salsa::{Durability, Setter};

pub use salsa::Cancelled;

use crate::{
    db::{line_index, parse, RootDatabase, SourceFile, Workspace, EDITED, UNEDITED},
    graph::{file_graphs, Graph},
    hir::{file_diagnostics, Diagnostic},
    ide,
    library::library_files,
    syntax::{TextRange, TextSize},
    text::{ColumnUnit, LineCol, LineIndex},
    Parse,
};

/// A file of the analysis: the handle [`AnalysisHost::add_file`] gives out.
pub type FileId = SourceFile;

/// The answer of a query, or `Cancelled` if a newer change made it moot.
pub type Cancellable<T> = Result<T, Cancelled>;

/// An edit as editors send it: a line/column range of the text as edited so far (none: the
/// whole text) and the text that replaces it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineColEdit {
    pub range: Option<(LineCol, LineCol)>,
    pub text: String,
}

/// Why an editor's change was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum InvalidEdit {
    /// Edit number `edit` (from 0) has a range that ends before it starts.
    ReversedRange { edit: usize, start: LineCol, end: LineCol },
    /// The file is the bundled library's, which is read-only.
    ReadOnly { path: String },
}

impl std::fmt::Display for InvalidEdit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InvalidEdit::ReversedRange { edit, start, end } => write!(
                f,
                "edit {edit} ends (line {}, column {}) before it starts (line {}, column {})",
                end.line, end.col, start.line, start.col
            ),
            InvalidEdit::ReadOnly { path } => {
                write!(f, "{path} is part of gudsl's bundled library, which is read-only")
            }
        }
    }
}

/// Owns the database; applies changes.
pub struct AnalysisHost {
    db: RootDatabase,
    workspace: Workspace,
    /// The bundled library's files ([`crate::library`]), first in every workspace.
    library: Vec<FileId>,
}

impl Default for AnalysisHost {
    fn default() -> Self {
        let db = RootDatabase::default();
        let library = library_files(&db);
        let workspace = Workspace::new(&db, library.clone());
        AnalysisHost { db, workspace, library }
    }
}

impl AnalysisHost {
    /// A host analysing `files` (path, text) together, in this order.
    pub fn with_files(files: impl IntoIterator<Item = (String, String)>) -> (AnalysisHost, Vec<FileId>) {
        let mut host = AnalysisHost::default();
        let ids: Vec<FileId> = files.into_iter().map(|(path, text)| host.add_file(path, text)).collect();
        host.set_workspace(ids.clone());
        (host, ids)
    }

    /// A new file (its path names it in messages). It is analysed once it is in the workspace.
    pub fn add_file(&mut self, path: String, text: String) -> FileId {
        SourceFile::builder(path, text).durability(UNEDITED).new(&self.db)
    }

    /// The files analysed together, in order (the first of two equal names is the one found),
    /// after the library's.
    pub fn set_workspace(&mut self, files: Vec<FileId>) {
        let files: Vec<FileId> = self.library.iter().copied().chain(files).collect();
        if self.workspace.files(&self.db) != &files {
            self.workspace.set_files(&mut self.db).to(files);
        }
    }

    /// Replaces a file's text (nothing is recomputed if it is the same): a text read from disk
    /// or opened in the editor ([`UNEDITED`]; edits are [`EDITED`]). The library's files are
    /// read-only: their text is never replaced.
    pub fn set_file_text(&mut self, file: FileId, text: String) {
        self.replace_text(file, text, UNEDITED);
    }

    /// The bundled library's files ([`crate::library`]), which every workspace has.
    pub fn library_files(&self) -> &[FileId] {
        &self.library
    }

    fn replace_text(&mut self, file: FileId, text: String, durability: Durability) {
        if self.library.contains(&file) {
            return;
        }
        if file.text(&self.db) != &text {
            file.set_text(&mut self.db).with_durability(durability).to(text);
        }
    }

    /// Applies editor edits in order, each against the text as changed so far; positions past a
    /// line's or the text's end clamp to it. An edit whose range ends before it starts refuses
    /// the whole change: nothing of it is applied.
    pub fn edit_file(&mut self, file: FileId, edits: Vec<LineColEdit>, unit: ColumnUnit) -> Result<(), InvalidEdit> {
        if self.library.contains(&file) {
            return Err(InvalidEdit::ReadOnly { path: file.path(&self.db).clone() });
        }
        let mut text = file.text(&self.db).clone();
        for (i, edit) in edits.into_iter().enumerate() {
            match edit.range {
                None => text = edit.text,
                Some((start, end)) => {
                    if end < start {
                        return Err(InvalidEdit::ReversedRange { edit: i, start, end });
                    }
                    let index = LineIndex::new(&text);
                    let offset = |at: LineCol| usize::from(index.offset(at, unit).unwrap_or(TextSize::of(&*text)));
                    text.replace_range(offset(start)..offset(end), &edit.text);
                }
            }
        }
        self.replace_text(file, text, EDITED);
        Ok(())
    }

    pub fn file_text(&self, file: FileId) -> &str {
        file.text(&self.db)
    }

    /// A snapshot to ask queries of.
    pub fn analysis(&self) -> Analysis {
        Analysis { db: self.db.clone(), workspace: self.workspace }
    }
}

/// A snapshot of the analysis. Queries return `Err(Cancelled)` once the host has changed.
#[derive(Clone)]
pub struct Analysis {
    db: RootDatabase,
    workspace: Workspace,
}

impl Analysis {
    fn with<'a, T>(&'a self, f: impl FnOnce(&'a RootDatabase, Workspace) -> T) -> Cancellable<T> {
        Cancelled::catch(AssertUnwindSafe(|| f(&self.db, self.workspace)))
    }

    /// `Err(Cancelled)` once a newer change waits for this snapshot: long work outside the
    /// queries (a conversion of a huge answer) calls it as it goes, so an edit never waits long.
    pub fn check_cancelled(&self) -> Cancellable<()> {
        self.with(|db, _| salsa::Database::unwind_if_revision_cancelled(db))
    }

    /// The files analysed together.
    pub fn files(&self) -> &[FileId] {
        self.workspace.files(&self.db)
    }

    pub fn file_text(&self, file: FileId) -> &str {
        file.text(&self.db)
    }

    /// The path a file was given, as messages name it.
    pub fn file_path(&self, file: FileId) -> &str {
        file.path(&self.db)
    }

    pub fn line_index(&self, file: FileId) -> Cancellable<&LineIndex> {
        self.with(|db, _| line_index(db, file))
    }

    pub fn parse(&self, file: FileId) -> Cancellable<&Parse> {
        self.with(|db, _| parse(db, file))
    }

    /// Every problem of a file (syntax, then semantics), by position, with the line index that
    /// places them: all a client needs to show them.
    pub fn diagnostics(&self, file: FileId) -> Cancellable<(&[Diagnostic], &LineIndex)> {
        self.with(|db, workspace| (file_diagnostics(db, workspace, file).as_slice(), line_index(db, file)))
    }

    /// The pipeline plan of the component-instance diagram `diagram` (fully qualified).
    pub fn pipeline_plan(&self, diagram: &str) -> Cancellable<Option<crate::hir::pipeline::PipelinePlan>> {
        self.with(|db, workspace| {
            crate::hir::pipeline::pipeline_plan(db, workspace, crate::hir::Fqn::new(db, diagram.to_string())).clone()
        })
    }

    /// Runs `f` on the semantic model of the workspace: how crates built on the model (the code
    /// generator) read it.
    pub fn with_semantics<T>(&self, f: impl FnOnce(&crate::hir::Semantics<'_>) -> T) -> Cancellable<T> {
        self.with(|db, workspace| f(&crate::hir::Semantics::new(db, workspace)))
    }

    /// Every diagram of a file as a graph (nested diagrams included).
    pub fn graphs(&self, file: FileId) -> Cancellable<&[Graph]> {
        self.with(|db, workspace| file_graphs(db, workspace, file).as_slice())
    }

    /// The formatted text, or `None` when the file has syntax errors.
    pub fn format(&self, file: FileId) -> Cancellable<Option<String>> {
        self.with(|db, _| crate::format::format(parse(db, file)))
    }

    pub fn document_symbols(&self, file: FileId) -> Cancellable<Vec<ide::Symbol>> {
        self.with(|db, _| ide::document_symbols(db, file))
    }

    pub fn folding_ranges(&self, file: FileId) -> Cancellable<Vec<ide::Fold>> {
        self.with(|db, _| ide::folding_ranges(&parse(db, file).syntax_node(), line_index(db, file)))
    }

    /// For each offset, the ranges to grow a selection through, innermost first.
    pub fn selection_ranges(&self, file: FileId, offsets: &[TextSize]) -> Cancellable<Vec<Vec<TextRange>>> {
        self.with(|db, _| {
            let root = parse(db, file).syntax_node();
            offsets.iter().map(|&offset| ide::selection_ranges(&root, offset)).collect()
        })
    }

    pub fn semantic_tokens(&self, file: FileId) -> Cancellable<Vec<ide::HighlightedToken>> {
        self.with(|db, _| ide::semantic_tokens(db, file))
    }

    pub fn goto_definition(&self, file: FileId, offset: TextSize) -> Cancellable<Vec<ide::NavigationTarget>> {
        self.with(|db, workspace| ide::goto_definition(db, workspace, file, offset))
    }

    pub fn goto_type_definition(&self, file: FileId, offset: TextSize) -> Cancellable<Vec<ide::NavigationTarget>> {
        self.with(|db, workspace| ide::goto_type_definition(db, workspace, file, offset))
    }

    /// Markdown for the name at `offset`, and the range it describes.
    pub fn hover(&self, file: FileId, offset: TextSize) -> Cancellable<Option<(TextRange, String)>> {
        self.with(|db, workspace| ide::hover(db, workspace, file, offset))
    }

    pub fn find_references(
        &self,
        file: FileId,
        offset: TextSize,
        include_declaration: bool,
    ) -> Cancellable<Vec<ide::FileRange>> {
        self.with(|db, workspace| ide::find_references(db, workspace, file, offset, include_declaration))
    }

    pub fn prepare_rename(&self, file: FileId, offset: TextSize) -> Cancellable<Result<TextRange, ide::RenameError>> {
        self.with(|db, workspace| ide::prepare_rename(db, workspace, file, offset))
    }

    pub fn rename(
        &self,
        file: FileId,
        offset: TextSize,
        new_name: &str,
    ) -> Cancellable<Result<Vec<(ide::FileRange, String)>, ide::RenameError>> {
        self.with(|db, workspace| ide::rename(db, workspace, file, offset, new_name))
    }

    /// The text edits that make `ops` on the diagram `diagram` of `file` (`gudsl/applyGraphEdit`).
    pub fn graph_edit(
        &self,
        file: FileId,
        diagram: &str,
        ops: &[ide::GraphOp],
    ) -> Cancellable<Result<Vec<(ide::FileRange, String)>, ide::GraphEditError>> {
        self.with(|db, workspace| ide::graph_edit(db, workspace, file, diagram, ops))
    }

    /// The edit of the text that sets `parameter` of the instance `instance` of the pipeline
    /// `diagram` (fully qualified) to `value` as written in the model.
    pub fn parameter_edit(
        &self,
        diagram: &str,
        instance: &str,
        parameter: &str,
        value: &str,
    ) -> Cancellable<Result<ide::ParameterEdit, String>> {
        self.with(|db, workspace| ide::parameter_edit(db, workspace, diagram, instance, parameter, value))
    }

    pub fn completions(&self, file: FileId, offset: TextSize) -> Cancellable<ide::Completions> {
        self.with(|db, workspace| ide::completions(db, workspace, file, offset))
    }

    pub fn signature_help(&self, file: FileId, offset: TextSize) -> Cancellable<Option<ide::SignatureHelp>> {
        self.with(|db, workspace| ide::signature_help(db, workspace, file, offset))
    }

    pub fn inlay_hints(&self, file: FileId, range: TextRange) -> Cancellable<Vec<ide::InlayHint>> {
        self.with(|db, _| ide::inlay_hints(db, file, range))
    }

    pub fn quick_fixes(&self, file: FileId, range: TextRange) -> Cancellable<Vec<ide::QuickFix>> {
        self.with(|db, workspace| ide::quick_fixes(db, workspace, file, range))
    }

    /// Diagrams and types whose name contains `query` (case-insensitive), at most `limit`.
    pub fn workspace_symbols(&self, query: &str, limit: usize) -> Cancellable<Vec<ide::WorkspaceSymbol>> {
        self.with(|db, workspace| ide::workspace_symbols(db, workspace, query, limit))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_in_utf16_apply_in_order_and_clamp() {
        let (mut host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), "// 😀 x\nabc".to_string())]);
        let at = |line, col| LineCol { line, col };
        host.edit_file(
            files[0],
            vec![
                // `x` sits at UTF-16 column 6 (the emoji counts 2); then past the end of line 1.
                LineColEdit { range: Some((at(0, 6), at(0, 7))), text: "y".into() },
                LineColEdit { range: Some((at(1, 9), at(5, 0))), text: "!".into() },
            ],
            ColumnUnit::Utf16,
        )
        .unwrap();
        assert_eq!(host.file_text(files[0]), "// 😀 y\nabc!");
        // A reversed range refuses the whole change, earlier edits included.
        let refused = host.edit_file(
            files[0],
            vec![
                LineColEdit { range: Some((at(0, 0), at(0, 0))), text: "lost".into() },
                LineColEdit { range: Some((at(1, 2), at(1, 1))), text: "?".into() },
            ],
            ColumnUnit::Utf16,
        );
        assert_eq!(refused, Err(InvalidEdit::ReversedRange { edit: 1, start: at(1, 2), end: at(1, 1) }));
        assert_eq!(host.file_text(files[0]), "// 😀 y\nabc!");
    }

    #[test]
    fn snapshots_see_the_text_of_their_time() {
        let (mut host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), "ClassDiagram A { }".to_string())]);
        assert_eq!(host.analysis().graphs(files[0]).unwrap()[0].id, "A");
        host.set_file_text(files[0], "ClassDiagram B { class C { public Missing m; } }".into());
        let analysis = host.analysis();
        assert_eq!(analysis.graphs(files[0]).unwrap()[0].id, "B");
        let (diagnostics, index) = analysis.diagnostics(files[0]).unwrap();
        assert_eq!(diagnostics.len(), 1);
        assert_eq!(index.line_col(diagnostics[0].range.start(), ColumnUnit::Utf8), LineCol { line: 0, col: 34 });
    }
}
