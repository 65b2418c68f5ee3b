//! The documents the server knows, by URI, and the model's [`AnalysisHost`] they live in. Edits
//! are applied here (on the message loop); requests read [`Snapshot`]s.

use std::{collections::HashMap, sync::Arc};

use gudsl_host::{access::Access, pipeline::Preparations};
use gudsl_model::{
    syntax::{TextRange, TextSize},
    Analysis, AnalysisHost, Cancellable, FileId, InvalidEdit, LineColEdit,
};
use tower_lsp_server::ls_types as lsp;

use super::{capabilities::Encoding, from_proto};

/// A document of the workspace.
#[derive(Clone)]
pub struct Document {
    pub uri: lsp::Uri,
    pub file: FileId,
    /// The editor's version while the document is open.
    pub version: Option<i32>,
    pub open: bool,
}

/// Why an editor's change was not applied.
#[derive(Debug, PartialEq, Eq)]
pub enum ChangeRefused {
    /// `didChange` for a document without `didOpen` (the spec allows changes to open ones only).
    NotOpen,
    /// A file of the bundled library, which is read-only.
    ReadOnly,
    Invalid(InvalidEdit),
}

/// The documents by URI, and the URI of each file (the bundled library's too: `gudsl:/lib/…`,
/// read-only, never published).
#[derive(Clone, Default)]
pub struct Documents {
    by_uri: HashMap<String, Document>,
    uris: HashMap<FileId, lsp::Uri>,
    library: HashMap<String, FileId>,
}

impl Documents {
    pub fn get(&self, uri: &str) -> Option<&Document> {
        self.by_uri.get(uri)
    }

    pub fn iter(&self) -> impl Iterator<Item = &Document> {
        self.by_uri.values()
    }

    pub fn contains(&self, uri: &str) -> bool {
        self.by_uri.contains_key(uri)
    }
}

pub struct Host {
    analysis: AnalysisHost,
    /// What the diagnostics of the pipelines prepared (`gudsl_host::pipeline::Preparations`).
    preparations: Arc<Preparations>,
    /// Shared with snapshots, copied only when changed while a snapshot holds it.
    documents: Arc<Documents>,
}

impl Default for Host {
    fn default() -> Host {
        let analysis = AnalysisHost::default();
        let mut documents = Documents::default();
        let snapshot = analysis.analysis();
        for &file in analysis.library_files() {
            let path = snapshot.file_path(file);
            if let Ok(uri) = path.parse::<lsp::Uri>() {
                documents.uris.insert(file, uri);
                documents.library.insert(path.to_string(), file);
            }
        }
        drop(snapshot);
        Host { analysis, preparations: Arc::default(), documents: Arc::new(documents) }
    }
}

impl Host {
    /// What the pipelines of the workspace may read (`initialize` sets it).
    pub fn set_access(&self, access: Access) {
        self.preparations.set_access(access);
    }

    /// Whether the client trusts the workspace (else nothing runs and no file a model names is
    /// read).
    pub fn trusted(&self) -> bool {
        self.preparations.access().trusted()
    }
}

/// A read-only view of the analysis and the documents at one moment. Its queries return
/// `Cancelled` as soon as the host applies a newer edit.
#[derive(Clone)]
pub struct Snapshot {
    pub analysis: Analysis,
    pub documents: Arc<Documents>,
    pub encoding: Encoding,
    /// The pipelines the diagnostics prepared, for ▶ Run pipeline to take.
    pub preparations: Arc<Preparations>,
}

impl Snapshot {
    pub fn document(&self, uri: &lsp::Uri) -> Option<&Document> {
        self.documents.get(uri.as_str())
    }

    /// The file of a document, or of the bundled library.
    pub fn file(&self, uri: &lsp::Uri) -> Option<FileId> {
        self.document(uri).map(|d| d.file).or_else(|| self.documents.library.get(uri.as_str()).copied())
    }

    /// Whether `uri` is a file of the bundled library (read-only).
    pub fn is_library(&self, uri: &lsp::Uri) -> bool {
        self.documents.library.contains_key(uri.as_str())
    }

    pub fn uri_of(&self, file: FileId) -> Option<lsp::Uri> {
        self.documents.uris.get(&file).cloned()
    }

    /// The file and byte offset a request points at; `None` for a document the server does not know.
    pub fn file_position(&self, uri: &lsp::Uri, position: lsp::Position) -> Cancellable<Option<(FileId, TextSize)>> {
        let Some(file) = self.file(uri) else { return Ok(None) };
        let index = self.analysis.line_index(file)?;
        Ok(Some((file, from_proto::offset(index, position, self.encoding))))
    }

    /// The file and byte range a request points at.
    pub fn file_range(&self, uri: &lsp::Uri, range: lsp::Range) -> Cancellable<Option<(FileId, TextRange)>> {
        let Some(file) = self.file(uri) else { return Ok(None) };
        let index = self.analysis.line_index(file)?;
        Ok(Some((file, from_proto::text_range(index, range, self.encoding))))
    }
}

/// How a file is named in messages: its path for `file:` URIs.
fn display_path(uri: &lsp::Uri) -> String {
    from_proto::file_path(uri).map_or_else(|| uri.as_str().to_string(), |p| p.display().to_string())
}

impl Host {
    pub fn snapshot(&self, encoding: Encoding) -> Snapshot {
        Snapshot {
            analysis: self.analysis.analysis(),
            documents: self.documents.clone(),
            encoding,
            preparations: self.preparations.clone(),
        }
    }

    /// The workspace is every known document, ordered by URI.
    fn sync_workspace(&mut self) {
        let mut files: Vec<(&String, FileId)> = self.documents.by_uri.iter().map(|(uri, d)| (uri, d.file)).collect();
        files.sort_by(|a, b| a.0.cmp(b.0));
        let files = files.into_iter().map(|(_, f)| f).collect();
        self.analysis.set_workspace(files);
    }

    /// Adds or replaces a document's text; `version` is set for documents the editor has open.
    /// A file of the bundled library keeps its text (an editor opens it to read it).
    pub fn set_text(&mut self, uri: &lsp::Uri, text: String, version: Option<i32>, open: bool) -> FileId {
        if let Some(&file) = self.documents.library.get(uri.as_str()) {
            return file;
        }
        let documents = Arc::make_mut(&mut self.documents);
        if let Some(document) = documents.by_uri.get_mut(uri.as_str()) {
            document.version = version;
            document.open = open;
            let file = document.file;
            self.analysis.set_file_text(file, text);
            return file;
        }
        let file = self.analysis.add_file(display_path(uri), text);
        documents.by_uri.insert(uri.as_str().to_string(), Document { uri: uri.clone(), file, version, open });
        documents.uris.insert(file, uri.clone());
        self.sync_workspace();
        file
    }

    /// Applies an editor's changes (incremental or full) to an open document; refused (nothing
    /// applied) for a document that is not open or a change with a reversed range.
    pub fn change(
        &mut self,
        uri: &lsp::Uri,
        version: i32,
        edits: Vec<LineColEdit>,
        encoding: Encoding,
    ) -> Result<FileId, ChangeRefused> {
        let file = match self.documents.get(uri.as_str()) {
            Some(document) if document.open => document.file,
            _ if self.documents.library.contains_key(uri.as_str()) => return Err(ChangeRefused::ReadOnly),
            _ => return Err(ChangeRefused::NotOpen),
        };
        self.analysis.edit_file(file, edits, encoding.0).map_err(ChangeRefused::Invalid)?;
        if let Some(document) = Arc::make_mut(&mut self.documents).by_uri.get_mut(uri.as_str()) {
            document.version = Some(version);
        }
        Ok(file)
    }

    /// The text the server has for a document (what `gudsl/viewFileText` shows).
    pub fn text(&self, uri: &lsp::Uri) -> Option<&str> {
        let file = self.documents.get(uri.as_str()).map(|d| d.file);
        file.or_else(|| self.documents.library.get(uri.as_str()).copied()).map(|file| self.analysis.file_text(file))
    }

    /// The editor closed the document: it stays in the workspace with its last text (the file
    /// watcher updates it from disk), without a version.
    pub fn close(&mut self, uri: &lsp::Uri) {
        if let Some(document) = Arc::make_mut(&mut self.documents).by_uri.get_mut(uri.as_str()) {
            document.open = false;
            document.version = None;
        }
    }

    pub fn remove(&mut self, uri: &lsp::Uri) {
        let documents = Arc::make_mut(&mut self.documents);
        if let Some(document) = documents.by_uri.remove(uri.as_str()) {
            documents.uris.remove(&document.file);
            self.sync_workspace();
        }
    }

    pub fn is_open(&self, uri: &lsp::Uri) -> bool {
        self.documents.get(uri.as_str()).is_some_and(|d| d.open)
    }
}

#[cfg(test)]
mod tests {
    use gudsl_model::text::ColumnUnit;

    use super::{super::from_proto, *};

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
        let edits = from_proto::edits(vec![change(((0, 6), (0, 7)), "y"), change(((1, 16), (1, 16)), " class C { }")]);
        let file = host.change(&uri, 2, edits, Encoding(ColumnUnit::Utf16)).unwrap();
        assert_eq!(host.analysis.file_text(file), "// 😀 y\nClassDiagram A { class C { } }\n");
        assert_eq!(host.snapshot(Encoding(ColumnUnit::Utf16)).document(&uri).unwrap().version, Some(2));
    }

    #[test]
    fn out_of_range_positions_clamp_instead_of_panicking() {
        let mut host = Host::default();
        let uri: lsp::Uri = "file:///ws/b.gudsl".parse().unwrap();
        host.set_text(&uri, "abc".to_string(), Some(1), true);
        let edits = from_proto::edits(vec![change(((5, 0), (9, 9)), "!")]);
        let file = host.change(&uri, 2, edits, Encoding(ColumnUnit::Utf8)).unwrap();
        assert_eq!(host.analysis.file_text(file), "abc!");
        let unknown = "file:///ws/unknown.gudsl".parse().unwrap();
        assert_eq!(host.change(&unknown, 1, vec![], Encoding(ColumnUnit::Utf8)), Err(ChangeRefused::NotOpen));
    }

    #[test]
    fn changes_to_closed_documents_and_reversed_ranges_are_refused() {
        let mut host = Host::default();
        let uri: lsp::Uri = "file:///ws/c.gudsl".parse().unwrap();
        // Loaded from disk, not opened: a change is not applied, and does not open it.
        host.set_text(&uri, "abc".to_string(), None, false);
        let edit = || from_proto::edits(vec![change(((0, 0), (0, 1)), "X")]);
        assert_eq!(host.change(&uri, 2, edit(), Encoding(ColumnUnit::Utf8)), Err(ChangeRefused::NotOpen));
        assert!(!host.is_open(&uri));
        assert_eq!(host.text(&uri), Some("abc"));
        host.set_text(&uri, "abc".to_string(), Some(1), true);
        let reversed = from_proto::edits(vec![change(((0, 2), (0, 1)), "X")]);
        assert!(matches!(host.change(&uri, 2, reversed, Encoding(ColumnUnit::Utf8)), Err(ChangeRefused::Invalid(_))));
        assert_eq!(host.text(&uri), Some("abc"));
        assert_eq!(host.snapshot(Encoding(ColumnUnit::Utf8)).document(&uri).unwrap().version, Some(1));
    }
}
