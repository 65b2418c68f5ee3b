//! The analysis host: the salsa database and the documents it knows, by URI. Edits are applied
//! here (on the message loop); requests read immutable snapshots.

use std::collections::HashMap;

use gudsl_model::{
    db::{line_index, RootDatabase, SourceFile, Workspace},
    syntax::TextSize,
};
use salsa::Setter;
use tower_lsp_server::ls_types as lsp;

use super::convert::Encoding;

/// A document of the workspace.
#[derive(Clone)]
pub struct Document {
    pub uri: lsp::Uri,
    pub file: SourceFile,
    /// The editor's version while the document is open.
    pub version: Option<i32>,
    pub open: bool,
}

pub struct Host {
    db: RootDatabase,
    workspace: Workspace,
    documents: HashMap<String, Document>,
}

/// A read-only view of the analysis at one moment. Queries on it are cancelled (they unwind
/// with `salsa::Cancelled`) as soon as the host applies a newer edit.
#[derive(Clone)]
pub struct Snapshot {
    pub db: RootDatabase,
    pub workspace: Workspace,
    pub documents: HashMap<String, Document>,
}

impl Snapshot {
    pub fn document(&self, uri: &lsp::Uri) -> Option<&Document> {
        self.documents.get(uri.as_str())
    }

    pub fn uri_of(&self, file: SourceFile) -> Option<lsp::Uri> {
        self.documents.values().find(|d| d.file == file).map(|d| d.uri.clone())
    }
}

impl Default for Host {
    fn default() -> Self {
        let db = RootDatabase::default();
        let workspace = Workspace::new(&db, Vec::new());
        Host { db, workspace, documents: HashMap::new() }
    }
}

/// How a file is named in messages: its path for `file:` URIs.
fn display_path(uri: &lsp::Uri) -> String {
    uri.to_file_path().map_or_else(|| uri.as_str().to_string(), |p| p.display().to_string())
}

impl Host {
    pub fn snapshot(&self) -> Snapshot {
        Snapshot { db: self.db.clone(), workspace: self.workspace, documents: self.documents.clone() }
    }

    fn sync_workspace(&mut self) {
        let mut files: Vec<(String, SourceFile)> =
            self.documents.iter().map(|(uri, d)| (uri.clone(), d.file)).collect();
        files.sort_by(|a, b| a.0.cmp(&b.0));
        self.workspace.set_files(&mut self.db).to(files.into_iter().map(|(_, f)| f).collect());
    }

    /// Adds or replaces a document's text; `version` is set for documents the editor has open.
    pub fn set_text(&mut self, uri: &lsp::Uri, text: String, version: Option<i32>, open: bool) -> SourceFile {
        if let Some(document) = self.documents.get_mut(uri.as_str()) {
            document.version = version;
            document.open = open;
            let file = document.file;
            if file.text(&self.db) != &text {
                file.set_text(&mut self.db).to(text);
            }
            return file;
        }
        let file = SourceFile::new(&self.db, display_path(uri), text);
        self.documents.insert(uri.as_str().to_string(), Document { uri: uri.clone(), file, version, open });
        self.sync_workspace();
        file
    }

    /// Applies an editor's changes (incremental or full) to an open document.
    pub fn change(
        &mut self,
        uri: &lsp::Uri,
        version: i32,
        changes: Vec<lsp::TextDocumentContentChangeEvent>,
        encoding: Encoding,
    ) -> Option<SourceFile> {
        let document = self.documents.get(uri.as_str())?;
        let file = document.file;
        let mut text = file.text(&self.db).clone();
        for change in changes {
            match change.range {
                None => text = change.text,
                Some(range) => {
                    // Positions refer to the text as changed so far.
                    let index = gudsl_model::text::LineIndex::new(&text);
                    let start: usize = encoding.offset(&index, text.len(), range.start).into();
                    let end: usize = encoding.offset(&index, text.len(), range.end).into();
                    let (start, end) = (start.min(end), end.max(start));
                    text.replace_range(start..end, &change.text);
                }
            }
        }
        Some(self.set_text(uri, text, Some(version), true))
    }

    /// The editor closed the document: it stays in the workspace with its last text (the file
    /// watcher updates it from disk), without a version.
    pub fn close(&mut self, uri: &lsp::Uri) {
        if let Some(document) = self.documents.get_mut(uri.as_str()) {
            document.open = false;
            document.version = None;
        }
    }

    pub fn remove(&mut self, uri: &lsp::Uri) {
        if self.documents.remove(uri.as_str()).is_some() {
            self.sync_workspace();
        }
    }

    pub fn is_open(&self, uri: &lsp::Uri) -> bool {
        self.documents.get(uri.as_str()).is_some_and(|d| d.open)
    }

    /// The byte offset of an LSP position in a document.
    pub fn offset(snapshot: &Snapshot, file: SourceFile, position: lsp::Position, encoding: Encoding) -> TextSize {
        let index = line_index(&snapshot.db, file);
        encoding.offset(index, file.text(&snapshot.db).len(), position)
    }
}

#[cfg(test)]
mod tests {
    use gudsl_model::text::ColumnUnit;

    use super::*;

    fn change(range: ((u32, u32), (u32, u32)), text: &str) -> lsp::TextDocumentContentChangeEvent {
        let ((l1, c1), (l2, c2)) = range;
        lsp::TextDocumentContentChangeEvent {
            range: Some(lsp::Range::new(lsp::Position::new(l1, c1), lsp::Position::new(l2, c2))),
            range_length: None,
            text: text.to_string(),
        }
    }

    #[test]
    fn incremental_changes_in_utf16_after_an_emoji() {
        let mut host = Host::default();
        let uri: lsp::Uri = "file:///ws/a.gudsl".parse().unwrap();
        host.set_text(&uri, "// 😀 x\nClassDiagram A { }\n".to_string(), Some(1), true);
        // Replace `x` (UTF-16 column 6: the emoji counts 2), then insert a class on line 1.
        let file = host
            .change(
                &uri,
                2,
                vec![change(((0, 6), (0, 7)), "y"), change(((1, 16), (1, 16)), " class C { }")],
                Encoding(ColumnUnit::Utf16),
            )
            .unwrap();
        assert_eq!(file.text(&host.db), "// 😀 y\nClassDiagram A { class C { } }\n");
        assert_eq!(host.snapshot().document(&uri).unwrap().version, Some(2));
    }

    #[test]
    fn out_of_range_positions_clamp_instead_of_panicking() {
        let mut host = Host::default();
        let uri: lsp::Uri = "file:///ws/b.gudsl".parse().unwrap();
        host.set_text(&uri, "abc".to_string(), Some(1), true);
        let file = host.change(&uri, 2, vec![change(((5, 0), (9, 9)), "!")], Encoding(ColumnUnit::Utf8)).unwrap();
        assert_eq!(file.text(&host.db), "abc!");
        assert!(host
            .change(&"file:///ws/unknown.gudsl".parse().unwrap(), 1, vec![], Encoding(ColumnUnit::Utf8))
            .is_none());
    }
}
