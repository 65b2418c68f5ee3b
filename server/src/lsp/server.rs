//! The LSP message loop's side: lifecycle, document sync, workspace loading and watching, and the
//! table of features (each delegating to `handlers` on a snapshot, off the loop).

use std::{
    collections::HashMap,
    panic::AssertUnwindSafe,
    path::PathBuf,
    sync::{
        atomic::{AtomicU64, Ordering},
        Arc, Mutex, OnceLock,
    },
    time::Instant,
};

use gudsl_host::access::Access;
use gudsl_model::{text::ColumnUnit, Cancellable, FileId};
use tower_lsp_server::{
    jsonrpc::{Error, ErrorCode, Result},
    ls_types as lsp, Client, LanguageServer,
};

use crate::workspace;

use super::{
    capabilities::{server_capabilities, Encoding},
    ext::GraphChangedNotification,
    from_proto, handlers,
    host::{ChangeRefused, Document, Host, Snapshot},
    invalid_params,
    jobs::Runs,
    lock, panic_text,
    preview::{Follower, Previews},
    request_failed, scenes, to_proto, CLIENT_ANSWER,
};

/// Diagnostics as last sent for a document, with the document version they were for.
type Published = (Option<i32>, Vec<lsp::Diagnostic>);

pub struct Backend {
    pub(super) client: Client,
    pub(super) host: Arc<Mutex<Host>>,
    encoding: OnceLock<Encoding>,
    roots: Mutex<Vec<PathBuf>>,
    /// The client accepts `window/workDoneProgress/create`.
    pub(super) progress_supported: std::sync::atomic::AtomicBool,
    /// Bumped by every edit; a diagnostics run publishes only if no newer edit came.
    generation: Arc<AtomicU64>,
    /// What was last published per URI (with the document version), so only changes are sent.
    published: Arc<Mutex<HashMap<String, Published>>>,
    /// Held while a diagnostics run publishes.
    publishing: Arc<tokio::sync::Mutex<()>>,
    /// The last semantic tokens sent per URI, with their result id, for delta requests.
    semantic_tokens: Mutex<HashMap<String, (String, Vec<u32>)>>,
    next_result_id: AtomicU64,
    /// The diagrams running now (▶ Run), to cancel them.
    pub(super) runs: Arc<Runs>,
    /// The scenes last laid out for `gudsl/graph`.
    pub(super) scenes: Arc<scenes::SceneCache>,
    /// The live preview (`gudsl.preview`).
    pub(super) previews: Arc<Previews>,
}

/// How long after publishing an edited document's diagnostics the other documents' are
/// computed: the publish is written meanwhile instead of competing with their work for the CPU
/// (bench.py linked, 200 files on 2 cores: keystroke -> diagnostics p95 9.6 ms without the pause,
/// 5.6 ms with 3 ms), and a keystroke typed meanwhile saves the work altogether.
const BACKGROUND_DELAY: std::time::Duration = std::time::Duration::from_millis(10);

impl Backend {
    pub fn new(client: Client) -> Backend {
        Backend {
            client,
            host: Arc::default(),
            encoding: OnceLock::new(),
            roots: Mutex::default(),
            progress_supported: Default::default(),
            generation: Arc::default(),
            published: Arc::default(),
            publishing: Arc::default(),
            semantic_tokens: Mutex::default(),
            next_result_id: AtomicU64::new(1),
            runs: Arc::default(),
            scenes: Arc::default(),
            previews: Arc::default(),
        }
    }

    pub(super) fn encoding(&self) -> Encoding {
        *self.encoding.get().unwrap_or(&Encoding(ColumnUnit::Utf16))
    }

    /// Runs `f` on a snapshot in a blocking task: cancelled by a newer edit (answered with
    /// `ContentModified`), and a panic is answered as an internal error, not a crash.
    pub(super) async fn on_snapshot<T: Send + 'static>(
        &self,
        f: impl FnOnce(&Snapshot) -> Cancellable<T> + Send + 'static,
    ) -> Result<T> {
        let snapshot = lock(&self.host).snapshot(self.encoding());
        let outcome =
            tokio::task::spawn_blocking(move || std::panic::catch_unwind(AssertUnwindSafe(|| f(&snapshot)))).await;
        match outcome {
            Ok(Ok(Ok(value))) => Ok(value),
            Ok(Ok(Err(_cancelled))) => Err(Error {
                code: ErrorCode::ContentModified,
                message: "the document changed; the request was cancelled".into(),
                data: None,
            }),
            Ok(Err(panic)) => {
                let what = panic_text(&*panic);
                self.client.log_message(lsp::MessageType::ERROR, format!("gudsl: request panicked: {what}")).await;
                Err(Error::internal_error())
            }
            Err(error) => {
                self.client.log_message(lsp::MessageType::ERROR, format!("gudsl: request task failed: {error}")).await;
                Err(Error::internal_error())
            }
        }
    }

    /// Computes the diagnostics of every document and publishes those that changed, unless a
    /// newer edit arrives first (then its own run publishes). The document just edited
    /// (`edited`) is computed and published first, before any other document's work; then the
    /// other open documents, then the rest of the workspace.
    fn schedule_diagnostics(&self, edited: Option<FileId>) {
        let received = Instant::now();
        let previews = self.previews.is_live().then(|| self.follower());
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let current = self.generation.clone();
        let host = self.host.clone();
        let client = self.client.clone();
        let published = self.published.clone();
        let publishing = self.publishing.clone();
        let scenes = self.scenes.clone();
        let encoding = self.encoding();
        tokio::spawn(async move {
            tokio::task::yield_now().await;
            // Phase 0: the edited document; 1: the other open ones; 2: the rest.
            let phase_of = |d: &Document| {
                if Some(d.file) == edited {
                    0
                } else if d.open {
                    1
                } else {
                    2
                }
            };
            const LAST_PHASE: usize = 2;
            for phase in 0..=LAST_PHASE {
                if let Some(follower) = previews.clone().filter(|_| phase == 1) {
                    // The edited document's diagnostics are out: the live preview follows.
                    tokio::spawn(follower.follow(received));
                }
                if phase == 1 && edited.is_some() {
                    tokio::time::sleep(BACKGROUND_DELAY).await;
                }
                if current.load(Ordering::SeqCst) != generation {
                    return;
                }
                let snapshot = lock(&host).snapshot(encoding);
                let documents = snapshot.documents.clone();
                let mut work: Vec<(lsp::Uri, Option<i32>, FileId)> = documents
                    .iter()
                    .filter(|d| phase_of(d) == phase)
                    .map(|d| (d.uri.clone(), d.version, d.file))
                    .collect();
                let last = phase == LAST_PHASE;
                if work.is_empty() && !last {
                    continue;
                }
                work.sort_by(|a, b| a.0.as_str().cmp(b.0.as_str()));
                let scenes = scenes.clone();
                let computed = tokio::task::spawn_blocking(move || {
                    let mut all = Vec::with_capacity(work.len());
                    for (uri, version, file) in work {
                        all.push((uri, version, handlers::diagnostics(&snapshot, file)?));
                    }
                    // Diagrams a client fetched that the edit changed (`gudsl/graphChanged`).
                    let redrawn = if phase == 0 { scenes.changed(&snapshot)? } else { Vec::new() };
                    Cancellable::Ok((all, redrawn))
                })
                .await;
                let Ok(Ok((all, redrawn))) = computed else { return };
                // One run publishes at a time, and only while it is the newest: an older run
                // cannot publish after a newer one (stale diagnostics, or ones just cleared).
                let _publishing = publishing.lock().await;
                if current.load(Ordering::SeqCst) != generation {
                    return;
                }
                let changed: Vec<_> = {
                    let mut published = lock(&published);
                    // Documents that left the workspace (closed unsaved, deleted): cleared, once
                    // every phase has published.
                    let mut cleared = Vec::new();
                    if last {
                        let forgotten: Vec<String> =
                            published.keys().filter(|uri| !documents.contains(uri)).cloned().collect();
                        for uri in forgotten {
                            published.remove(&uri);
                            cleared.extend(uri.parse::<lsp::Uri>().ok().map(|uri| (uri, None, Vec::new())));
                        }
                    }
                    // A new version of an open document is always answered, so the editor knows
                    // its diagnostics are current; other documents only when they change.
                    all.into_iter()
                        .filter(|(uri, version, diagnostics)| {
                            let unchanged =
                                published.get(uri.as_str()).is_some_and(|(v, d)| v == version && d == diagnostics);
                            if !unchanged {
                                published.insert(uri.as_str().to_string(), (*version, diagnostics.clone()));
                            }
                            !unchanged
                        })
                        .chain(cleared)
                        .collect()
                };
                for (uri, version, diagnostics) in changed {
                    client.publish_diagnostics(uri, diagnostics, version).await;
                }
                for changed in redrawn {
                    client.send_notification::<GraphChangedNotification>(changed).await;
                }
            }
        });
    }

    /// What the live preview follows edits with.
    fn follower(&self) -> Follower {
        Follower {
            previews: self.previews.clone(),
            host: self.host.clone(),
            client: self.client.clone(),
            encoding: self.encoding(),
            scenes: self.scenes.clone(),
        }
    }

    /// Runs the live preview after an edit received at `received`, if one is live.
    pub(super) fn follow_preview(&self, received: Instant) {
        tokio::spawn(self.follower().follow(received));
    }

    /// Loads every `.gudsl` file under the workspace roots, reporting progress.
    async fn load_workspace(&self) {
        let roots = lock(&self.roots).clone();
        let mut errors = Vec::new();
        let mut paths = workspace::document_paths(&roots, &mut errors);
        paths.sort();
        for error in errors {
            self.client.log_message(lsp::MessageType::WARNING, format!("gudsl: {error}")).await;
        }
        let token = lsp::ProgressToken::String("gudsl/load".to_string());
        let progress_supported = self.progress_supported.load(Ordering::SeqCst)
            && tokio::time::timeout(CLIENT_ANSWER, self.client.create_work_done_progress(token.clone()))
                .await
                .is_ok_and(|answer| answer.is_ok());
        let progress = if progress_supported {
            Some(
                self.client
                    .progress(token, "Loading GU-DSL workspace")
                    .with_percentage(0)
                    .with_message(format!("{} files", paths.len()))
                    .begin()
                    .await,
            )
        } else {
            None
        };
        let total = paths.len().max(1);
        for (i, path) in paths.iter().enumerate() {
            let Some(uri) = lsp::Uri::from_file_path(path) else { continue };
            let text = match workspace::read_text(path) {
                Ok(text) => text,
                Err(error) => {
                    self.client.log_message(lsp::MessageType::WARNING, format!("gudsl: {error}: not loaded")).await;
                    continue;
                }
            };
            {
                let mut host = lock(&self.host);
                if !host.is_open(&uri) {
                    host.set_text(&uri, text, None, false);
                }
            }
            if let Some(progress) = &progress {
                if i % 20 == 0 {
                    progress.report_with_message(format!("{}/{}", i + 1, paths.len()), (i * 100 / total) as u32).await;
                }
            }
        }
        if let Some(progress) = progress {
            progress.finish_with_message(format!("{} files loaded", paths.len())).await;
        }
        self.schedule_diagnostics(None);
    }
}

/// Asks the client to report changes of `.gudsl` files on disk.
async fn watch_files(client: &Client) {
    let options = lsp::DidChangeWatchedFilesRegistrationOptions {
        watchers: vec![lsp::FileSystemWatcher {
            glob_pattern: lsp::GlobPattern::String("**/*.gudsl".to_string()),
            kind: None,
        }],
    };
    let registration = lsp::Registration {
        id: "gudsl-watch".to_string(),
        method: "workspace/didChangeWatchedFiles".to_string(),
        register_options: serde_json::to_value(options).ok(),
    };
    // Clients without dynamic registration simply refuse; the server works without it.
    let _ = client.register_capability(vec![registration]).await;
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: lsp::InitializeParams) -> Result<lsp::InitializeResult> {
        let encoding = Encoding::negotiate(&params.capabilities);
        let progress = params.capabilities.window.as_ref().and_then(|w| w.work_done_progress).unwrap_or(false);
        self.progress_supported.store(progress, Ordering::SeqCst);
        let _ = self.encoding.set(encoding);
        let mut roots: Vec<PathBuf> =
            params.workspace_folders.unwrap_or_default().iter().filter_map(|f| from_proto::file_path(&f.uri)).collect();
        #[allow(deprecated)] // `root_uri` is what older clients send.
        if roots.is_empty() {
            roots.extend(params.root_uri.as_ref().and_then(from_proto::file_path));
        }
        let trusted = params.initialization_options.as_ref().and_then(|o| o.get("trusted")).and_then(|t| t.as_bool());
        lock(&self.host).set_access(Access::new(roots.clone(), trusted.unwrap_or(true)));
        *lock(&self.roots) = roots;
        Ok(lsp::InitializeResult {
            server_info: Some(lsp::ServerInfo {
                name: "gudsl".into(),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            }),
            capabilities: server_capabilities(encoding),
            ..Default::default()
        })
    }

    async fn initialized(&self, _: lsp::InitializedParams) {
        // The registration is not waited for: a client that never answers still gets its
        // workspace loaded.
        let client = self.client.clone();
        tokio::spawn(async move { watch_files(&client).await });
        self.load_workspace().await;
    }

    async fn shutdown(&self) -> Result<()> {
        Ok(())
    }

    async fn did_open(&self, params: lsp::DidOpenTextDocumentParams) {
        let doc = params.text_document;
        let file = lock(&self.host).set_text(&doc.uri, doc.text, Some(doc.version), true);
        self.schedule_diagnostics(Some(file));
    }

    async fn did_change(&self, params: lsp::DidChangeTextDocumentParams) {
        let encoding = self.encoding();
        let doc = params.text_document;
        let edits = from_proto::edits(params.content_changes);
        let refused = lock(&self.host).change(&doc.uri, doc.version, edits, encoding);
        match refused {
            Ok(file) => self.schedule_diagnostics(Some(file)),
            Err(ChangeRefused::ReadOnly) => {
                let message = format!(
                    "gudsl: {} is part of gudsl's bundled library, which is read-only: the change was not applied",
                    doc.uri.as_str()
                );
                self.client.show_message(lsp::MessageType::WARNING, message).await;
            }
            Err(ChangeRefused::NotOpen) => {
                let message =
                    format!("gudsl: ignored a change to {}, which is not open (no didOpen)", doc.uri.as_str());
                self.client.log_message(lsp::MessageType::WARNING, message).await;
            }
            Err(ChangeRefused::Invalid(why)) => {
                let message = format!(
                    "gudsl: a change to {} was not applied: {why}. The server's copy may now differ from the editor's: close and reopen the file.",
                    doc.uri.as_str()
                );
                self.client.show_message(lsp::MessageType::ERROR, message).await;
            }
        }
    }

    async fn did_save(&self, params: lsp::DidSaveTextDocumentParams) {
        // The rows of the diagrams drawn are saved with the model: the next fresh layout (a new
        // session, `gudsl render`) keeps them.
        let uri = params.text_document.uri;
        let scenes = self.scenes.clone();
        let saved = self.on_snapshot(move |snap| Ok(super::graph_edit::remember_rows(snap, &uri, &scenes))).await;
        if let Ok(Err(error)) = saved {
            self.client
                .log_message(lsp::MessageType::WARNING, format!("gudsl: the diagrams' rows were not saved: {error}"))
                .await;
        }
    }

    async fn did_close(&self, params: lsp::DidCloseTextDocumentParams) {
        let uri = params.text_document.uri;
        // Back to the disk's version (the editor may close without saving) for a file of the
        // workspace folders; a file outside them, unsaved or deleted leaves the workspace (and
        // its diagnostics are cleared).
        let path = from_proto::file_path(&uri);
        let in_workspace = path.as_ref().is_some_and(|p| lock(&self.roots).iter().any(|root| p.starts_with(root)));
        let on_disk = path.filter(|_| in_workspace).and_then(|p| workspace::read_text(&p).ok());
        {
            let mut host = lock(&self.host);
            match on_disk {
                Some(text) => {
                    host.set_text(&uri, text, None, false);
                }
                None => host.remove(&uri),
            }
            host.close(&uri);
        }
        self.schedule_diagnostics(None);
    }

    async fn did_change_watched_files(&self, params: lsp::DidChangeWatchedFilesParams) {
        {
            let mut host = lock(&self.host);
            for change in params.changes {
                if host.is_open(&change.uri) {
                    continue; // The editor's text wins over the disk's.
                }
                if change.typ == lsp::FileChangeType::DELETED {
                    host.remove(&change.uri);
                } else if let Some(text) =
                    from_proto::file_path(&change.uri).and_then(|p| workspace::read_text(&p).ok())
                {
                    host.set_text(&change.uri, text, None, false);
                }
            }
        }
        self.schedule_diagnostics(None);
    }

    async fn document_symbol(&self, params: lsp::DocumentSymbolParams) -> Result<Option<lsp::DocumentSymbolResponse>> {
        self.on_snapshot(move |s| handlers::document_symbols(s, &params.text_document.uri)).await
    }

    async fn goto_definition(&self, params: lsp::GotoDefinitionParams) -> Result<Option<lsp::GotoDefinitionResponse>> {
        self.on_snapshot(move |s| handlers::goto_definition(s, params.text_document_position_params)).await
    }

    async fn goto_type_definition(
        &self,
        params: lsp::request::GotoTypeDefinitionParams,
    ) -> Result<Option<lsp::request::GotoTypeDefinitionResponse>> {
        self.on_snapshot(move |s| handlers::goto_type_definition(s, params.text_document_position_params)).await
    }

    async fn hover(&self, params: lsp::HoverParams) -> Result<Option<lsp::Hover>> {
        self.on_snapshot(move |s| handlers::hover(s, params.text_document_position_params)).await
    }

    async fn folding_range(&self, params: lsp::FoldingRangeParams) -> Result<Option<Vec<lsp::FoldingRange>>> {
        self.on_snapshot(move |s| handlers::folding_ranges(s, &params.text_document.uri)).await
    }

    async fn completion(&self, params: lsp::CompletionParams) -> Result<Option<lsp::CompletionResponse>> {
        self.on_snapshot(move |s| handlers::completion(s, params.text_document_position)).await
    }

    async fn selection_range(&self, params: lsp::SelectionRangeParams) -> Result<Option<Vec<lsp::SelectionRange>>> {
        self.on_snapshot(move |s| handlers::selection_ranges(s, params)).await
    }

    async fn symbol(&self, params: lsp::WorkspaceSymbolParams) -> Result<Option<lsp::WorkspaceSymbolResponse>> {
        let symbols = self.on_snapshot(move |s| handlers::workspace_symbols(s, &params.query)).await?;
        Ok(Some(lsp::WorkspaceSymbolResponse::Flat(symbols)))
    }

    async fn semantic_tokens_full(
        &self,
        params: lsp::SemanticTokensParams,
    ) -> Result<Option<lsp::SemanticTokensResult>> {
        let uri = params.text_document.uri;
        let key = uri.as_str().to_string();
        let Some(data) = self.on_snapshot(move |s| handlers::semantic_token_data(s, &uri)).await? else {
            return Ok(None);
        };
        let id = self.next_result_id.fetch_add(1, Ordering::SeqCst).to_string();
        let tokens = to_proto::semantic_tokens(&data);
        lock(&self.semantic_tokens).insert(key, (id.clone(), data));
        Ok(Some(lsp::SemanticTokensResult::Tokens(lsp::SemanticTokens { result_id: Some(id), data: tokens })))
    }

    async fn semantic_tokens_full_delta(
        &self,
        params: lsp::SemanticTokensDeltaParams,
    ) -> Result<Option<lsp::SemanticTokensFullDeltaResult>> {
        let uri = params.text_document.uri;
        let key = uri.as_str().to_string();
        let Some(data) = self.on_snapshot(move |s| handlers::semantic_token_data(s, &uri)).await? else {
            return Ok(None);
        };
        let id = self.next_result_id.fetch_add(1, Ordering::SeqCst).to_string();
        let previous = lock(&self.semantic_tokens).insert(key, (id.clone(), data.clone()));
        Ok(Some(match previous.filter(|(old_id, _)| *old_id == params.previous_result_id) {
            Some((_, old)) => lsp::SemanticTokensFullDeltaResult::TokensDelta(lsp::SemanticTokensDelta {
                result_id: Some(id),
                edits: to_proto::semantic_token_edit(&old, &data),
            }),
            None => lsp::SemanticTokensFullDeltaResult::Tokens(lsp::SemanticTokens {
                result_id: Some(id),
                data: to_proto::semantic_tokens(&data),
            }),
        }))
    }

    async fn code_action(&self, params: lsp::CodeActionParams) -> Result<Option<lsp::CodeActionResponse>> {
        from_proto::ordered_range(params.range).map_err(invalid_params)?;
        self.on_snapshot(move |s| handlers::code_actions(s, params)).await
    }

    async fn inlay_hint(&self, params: lsp::InlayHintParams) -> Result<Option<Vec<lsp::InlayHint>>> {
        from_proto::ordered_range(params.range).map_err(invalid_params)?;
        self.on_snapshot(move |s| handlers::inlay_hints(s, params)).await
    }

    async fn signature_help(&self, params: lsp::SignatureHelpParams) -> Result<Option<lsp::SignatureHelp>> {
        self.on_snapshot(move |s| handlers::signature_help(s, params.text_document_position_params)).await
    }

    async fn formatting(&self, params: lsp::DocumentFormattingParams) -> Result<Option<Vec<lsp::TextEdit>>> {
        self.on_snapshot(move |s| handlers::formatting(s, &params.text_document.uri)).await
    }

    async fn references(&self, params: lsp::ReferenceParams) -> Result<Option<Vec<lsp::Location>>> {
        self.on_snapshot(move |s| handlers::references(s, params)).await
    }

    async fn document_highlight(
        &self,
        params: lsp::DocumentHighlightParams,
    ) -> Result<Option<Vec<lsp::DocumentHighlight>>> {
        self.on_snapshot(move |s| handlers::document_highlight(s, params.text_document_position_params)).await
    }

    async fn prepare_rename(
        &self,
        params: lsp::TextDocumentPositionParams,
    ) -> Result<Option<lsp::PrepareRenameResponse>> {
        self.on_snapshot(move |s| handlers::prepare_rename(s, params)).await?.map_err(request_failed)
    }

    async fn rename(&self, params: lsp::RenameParams) -> Result<Option<lsp::WorkspaceEdit>> {
        self.on_snapshot(move |s| handlers::rename(s, params)).await?.map_err(request_failed)
    }

    async fn code_lens(&self, params: lsp::CodeLensParams) -> Result<Option<Vec<lsp::CodeLens>>> {
        self.on_snapshot(move |s| handlers::code_lenses(s, &params.text_document.uri)).await
    }

    async fn execute_command(&self, params: lsp::ExecuteCommandParams) -> Result<Option<lsp::LSPAny>> {
        self.execute(params).await
    }
}
