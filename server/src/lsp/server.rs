//! The LSP message handlers: lifecycle, document sync, workspace loading and watching, and the
//! table of features (each delegating to `handlers` on a snapshot).

use std::{
    collections::HashMap,
    panic::AssertUnwindSafe,
    path::PathBuf,
    sync::{
        atomic::{AtomicU64, Ordering},
        Arc, Mutex, OnceLock,
    },
};

use gudsl_model::text::ColumnUnit;
use tower_lsp_server::{
    jsonrpc::{Error, ErrorCode, Result},
    ls_types as lsp, Client, LanguageServer,
};

use crate::workspace;

use super::{
    convert::Encoding,
    handlers,
    host::{Host, Snapshot},
};

/// Diagnostics as last sent for a document, with the document version they were for.
type Published = (Option<i32>, Vec<lsp::Diagnostic>);

pub struct Backend {
    client: Client,
    host: Arc<Mutex<Host>>,
    encoding: OnceLock<Encoding>,
    roots: Mutex<Vec<PathBuf>>,
    /// The client accepts `window/workDoneProgress/create`.
    progress_supported: std::sync::atomic::AtomicBool,
    /// Bumped by every edit; a diagnostics run publishes only if no newer edit came.
    generation: Arc<AtomicU64>,
    /// What was last published per URI (with the document version), so only changes are sent.
    published: Arc<Mutex<HashMap<String, Published>>>,
    /// The last semantic tokens sent per URI, with their result id, for delta requests.
    semantic_tokens: Mutex<HashMap<String, (String, Vec<u32>)>>,
    next_result_id: AtomicU64,
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

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
            semantic_tokens: Mutex::default(),
            next_result_id: AtomicU64::new(1),
        }
    }

    fn encoding(&self) -> Encoding {
        *self.encoding.get().unwrap_or(&Encoding(ColumnUnit::Utf16))
    }

    /// Runs `f` on a snapshot in a blocking task: cancelled by a newer edit (answered with
    /// `ContentModified`), and a panic is answered as an internal error, not a crash.
    async fn on_snapshot<T: Send + 'static>(&self, f: impl FnOnce(&Snapshot) -> T + Send + 'static) -> Result<T> {
        let snapshot = lock(&self.host).snapshot();
        let outcome = tokio::task::spawn_blocking(move || {
            std::panic::catch_unwind(AssertUnwindSafe(|| salsa::Cancelled::catch(AssertUnwindSafe(|| f(&snapshot)))))
        })
        .await;
        match outcome {
            Ok(Ok(Ok(value))) => Ok(value),
            Ok(Ok(Err(_cancelled))) => Err(Error {
                code: ErrorCode::ContentModified,
                message: "the document changed; the request was cancelled".into(),
                data: None,
            }),
            Ok(Err(panic)) => {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "unknown panic".into());
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
    /// newer edit arrives first (then its own run publishes). Open documents go first, so the
    /// one being typed in is answered before the rest of the workspace is re-checked.
    fn schedule_diagnostics(&self) {
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let current = self.generation.clone();
        let host = self.host.clone();
        let client = self.client.clone();
        let published = self.published.clone();
        let encoding = self.encoding();
        tokio::spawn(async move {
            tokio::task::yield_now().await;
            for open_phase in [true, false] {
                if current.load(Ordering::SeqCst) != generation {
                    return;
                }
                let snapshot = lock(&host).snapshot();
                let computed = tokio::task::spawn_blocking(move || {
                    salsa::Cancelled::catch(AssertUnwindSafe(|| {
                        let mut all: Vec<(lsp::Uri, Option<i32>, Vec<lsp::Diagnostic>)> = snapshot
                            .documents
                            .values()
                            .filter(|d| d.open == open_phase)
                            .map(|d| (d.uri.clone(), d.version, handlers::diagnostics(&snapshot, d.file, encoding)))
                            .collect();
                        all.sort_by(|a, b| a.0.as_str().cmp(b.0.as_str()));
                        all
                    }))
                })
                .await;
                let Ok(Ok(all)) = computed else { return };
                if current.load(Ordering::SeqCst) != generation {
                    return;
                }
                let changed: Vec<_> = {
                    let mut published = lock(&published);
                    // A new version of an open document is always answered, so the editor knows
                    // its diagnostics are current; other documents only when they change.
                    all.into_iter()
                        .filter(|(uri, version, diagnostics)| {
                            let current = (*version, diagnostics.clone());
                            let unchanged = published.get(uri.as_str()) == Some(&current);
                            if !unchanged {
                                published.insert(uri.as_str().to_string(), current);
                            }
                            !unchanged
                        })
                        .collect()
                };
                for (uri, version, diagnostics) in changed {
                    client.publish_diagnostics(uri, diagnostics, version).await;
                }
            }
        });
    }

    /// Loads every `.gudsl` file under the workspace roots, reporting progress.
    async fn load_workspace(&self) {
        let roots = lock(&self.roots).clone();
        let mut paths = Vec::new();
        let mut errors = Vec::new();
        for root in &roots {
            paths.extend(workspace::gudsl_files(root, &mut errors));
        }
        paths.sort();
        for error in errors {
            self.client.log_message(lsp::MessageType::WARNING, format!("gudsl: {error}")).await;
        }
        let token = lsp::ProgressToken::String("gudsl/load".to_string());
        let progress_supported = self.progress_supported.load(Ordering::SeqCst)
            && self.client.create_work_done_progress(token.clone()).await.is_ok();
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
            let Ok(text) = workspace::read_text(path) else { continue };
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
        self.schedule_diagnostics();
    }

    async fn watch_files(&self) {
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
        let _ = self.client.register_capability(vec![registration]).await;
    }
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: lsp::InitializeParams) -> Result<lsp::InitializeResult> {
        let encoding = Encoding::negotiate(&params.capabilities);
        let progress = params.capabilities.window.as_ref().and_then(|w| w.work_done_progress).unwrap_or(false);
        self.progress_supported.store(progress, Ordering::SeqCst);
        let _ = self.encoding.set(encoding);
        let mut roots: Vec<PathBuf> = params
            .workspace_folders
            .unwrap_or_default()
            .iter()
            .filter_map(|f| f.uri.to_file_path().map(|p| p.into_owned()))
            .collect();
        #[allow(deprecated)] // `root_uri` is what older clients send.
        if roots.is_empty() {
            roots.extend(params.root_uri.as_ref().and_then(|u| u.to_file_path().map(|p| p.into_owned())));
        }
        *lock(&self.roots) = roots;
        Ok(lsp::InitializeResult {
            server_info: Some(lsp::ServerInfo {
                name: "gudsl".into(),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            }),
            capabilities: lsp::ServerCapabilities {
                position_encoding: Some(encoding.kind()),
                text_document_sync: Some(lsp::TextDocumentSyncCapability::Options(lsp::TextDocumentSyncOptions {
                    open_close: Some(true),
                    change: Some(lsp::TextDocumentSyncKind::INCREMENTAL),
                    ..Default::default()
                })),
                document_symbol_provider: Some(lsp::OneOf::Left(true)),
                definition_provider: Some(lsp::OneOf::Left(true)),
                type_definition_provider: Some(lsp::TypeDefinitionProviderCapability::Simple(true)),
                hover_provider: Some(lsp::HoverProviderCapability::Simple(true)),
                folding_range_provider: Some(lsp::FoldingRangeProviderCapability::Simple(true)),
                references_provider: Some(lsp::OneOf::Left(true)),
                completion_provider: Some(lsp::CompletionOptions {
                    trigger_characters: Some([".", ">", ":", "("].iter().map(|c| c.to_string()).collect()),
                    ..Default::default()
                }),
                document_formatting_provider: Some(lsp::OneOf::Left(true)),
                inlay_hint_provider: Some(lsp::OneOf::Left(true)),
                signature_help_provider: Some(lsp::SignatureHelpOptions {
                    trigger_characters: Some(vec!["(".into(), ",".into()]),
                    retrigger_characters: None,
                    work_done_progress_options: Default::default(),
                }),
                code_action_provider: Some(lsp::CodeActionProviderCapability::Options(lsp::CodeActionOptions {
                    code_action_kinds: Some(vec![lsp::CodeActionKind::QUICKFIX]),
                    ..Default::default()
                })),
                selection_range_provider: Some(lsp::SelectionRangeProviderCapability::Simple(true)),
                workspace_symbol_provider: Some(lsp::OneOf::Left(true)),
                semantic_tokens_provider: Some(lsp::SemanticTokensServerCapabilities::SemanticTokensOptions(
                    lsp::SemanticTokensOptions {
                        legend: handlers::semantic_token_legend(),
                        full: Some(lsp::SemanticTokensFullOptions::Delta { delta: Some(true) }),
                        range: None,
                        work_done_progress_options: Default::default(),
                    },
                )),
                document_highlight_provider: Some(lsp::OneOf::Left(true)),
                rename_provider: Some(lsp::OneOf::Right(lsp::RenameOptions {
                    prepare_provider: Some(true),
                    work_done_progress_options: Default::default(),
                })),
                ..Default::default()
            },
            ..Default::default()
        })
    }

    async fn initialized(&self, _: lsp::InitializedParams) {
        self.watch_files().await;
        self.load_workspace().await;
    }

    async fn shutdown(&self) -> Result<()> {
        Ok(())
    }

    async fn did_open(&self, params: lsp::DidOpenTextDocumentParams) {
        let doc = params.text_document;
        lock(&self.host).set_text(&doc.uri, doc.text, Some(doc.version), true);
        self.schedule_diagnostics();
    }

    async fn did_change(&self, params: lsp::DidChangeTextDocumentParams) {
        let encoding = self.encoding();
        let doc = params.text_document;
        let applied = lock(&self.host).change(&doc.uri, doc.version, params.content_changes, encoding);
        if applied.is_none() {
            self.client
                .log_message(
                    lsp::MessageType::WARNING,
                    format!("gudsl: change to unknown document {}", doc.uri.as_str()),
                )
                .await;
        }
        self.schedule_diagnostics();
    }

    async fn did_close(&self, params: lsp::DidCloseTextDocumentParams) {
        let uri = params.text_document.uri;
        // Back to the disk's version (the editor may close without saving).
        let on_disk = uri.to_file_path().and_then(|p| workspace::read_text(&p).ok());
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
        self.schedule_diagnostics();
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
                } else if let Some(text) = change.uri.to_file_path().and_then(|p| workspace::read_text(&p).ok()) {
                    host.set_text(&change.uri, text, None, false);
                }
            }
        }
        self.schedule_diagnostics();
    }

    async fn document_symbol(&self, params: lsp::DocumentSymbolParams) -> Result<Option<lsp::DocumentSymbolResponse>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::document_symbols(s, &params.text_document.uri, encoding)).await
    }

    async fn goto_definition(&self, params: lsp::GotoDefinitionParams) -> Result<Option<lsp::GotoDefinitionResponse>> {
        let encoding = self.encoding();
        let at = params.text_document_position_params;
        self.on_snapshot(move |s| handlers::goto_definition(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn goto_type_definition(
        &self,
        params: lsp::request::GotoTypeDefinitionParams,
    ) -> Result<Option<lsp::request::GotoTypeDefinitionResponse>> {
        let encoding = self.encoding();
        let at = params.text_document_position_params;
        self.on_snapshot(move |s| handlers::goto_type_definition(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn hover(&self, params: lsp::HoverParams) -> Result<Option<lsp::Hover>> {
        let encoding = self.encoding();
        let at = params.text_document_position_params;
        self.on_snapshot(move |s| handlers::hover(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn folding_range(&self, params: lsp::FoldingRangeParams) -> Result<Option<Vec<lsp::FoldingRange>>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::folding_ranges(s, &params.text_document.uri, encoding)).await
    }

    async fn completion(&self, params: lsp::CompletionParams) -> Result<Option<lsp::CompletionResponse>> {
        let encoding = self.encoding();
        let at = params.text_document_position;
        self.on_snapshot(move |s| handlers::completion(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn selection_range(&self, params: lsp::SelectionRangeParams) -> Result<Option<Vec<lsp::SelectionRange>>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::selection_ranges(s, &params.text_document.uri, &params.positions, encoding))
            .await
    }

    async fn symbol(&self, params: lsp::WorkspaceSymbolParams) -> Result<Option<lsp::WorkspaceSymbolResponse>> {
        let encoding = self.encoding();
        let symbols = self.on_snapshot(move |s| handlers::workspace_symbols(s, &params.query, encoding)).await?;
        Ok(Some(lsp::WorkspaceSymbolResponse::Flat(symbols)))
    }

    async fn semantic_tokens_full(
        &self,
        params: lsp::SemanticTokensParams,
    ) -> Result<Option<lsp::SemanticTokensResult>> {
        let encoding = self.encoding();
        let uri = params.text_document.uri;
        let key = uri.as_str().to_string();
        let Some(data) = self.on_snapshot(move |s| handlers::semantic_token_data(s, &uri, encoding)).await? else {
            return Ok(None);
        };
        let id = self.next_result_id.fetch_add(1, Ordering::SeqCst).to_string();
        let tokens = handlers::semantic_token_edit(&[], &data).pop().and_then(|e| e.data).unwrap_or_default();
        lock(&self.semantic_tokens).insert(key, (id.clone(), data));
        Ok(Some(lsp::SemanticTokensResult::Tokens(lsp::SemanticTokens { result_id: Some(id), data: tokens })))
    }

    async fn semantic_tokens_full_delta(
        &self,
        params: lsp::SemanticTokensDeltaParams,
    ) -> Result<Option<lsp::SemanticTokensFullDeltaResult>> {
        let encoding = self.encoding();
        let uri = params.text_document.uri;
        let key = uri.as_str().to_string();
        let Some(data) = self.on_snapshot(move |s| handlers::semantic_token_data(s, &uri, encoding)).await? else {
            return Ok(None);
        };
        let id = self.next_result_id.fetch_add(1, Ordering::SeqCst).to_string();
        let previous = lock(&self.semantic_tokens).insert(key, (id.clone(), data.clone()));
        Ok(Some(match previous.filter(|(old_id, _)| *old_id == params.previous_result_id) {
            Some((_, old)) => lsp::SemanticTokensFullDeltaResult::TokensDelta(lsp::SemanticTokensDelta {
                result_id: Some(id),
                edits: handlers::semantic_token_edit(&old, &data),
            }),
            None => {
                let tokens = handlers::semantic_token_edit(&[], &data).pop().and_then(|e| e.data).unwrap_or_default();
                lsp::SemanticTokensFullDeltaResult::Tokens(lsp::SemanticTokens { result_id: Some(id), data: tokens })
            }
        }))
    }

    async fn code_action(&self, params: lsp::CodeActionParams) -> Result<Option<lsp::CodeActionResponse>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::code_actions(s, &params.text_document.uri, params.range, encoding)).await
    }

    async fn inlay_hint(&self, params: lsp::InlayHintParams) -> Result<Option<Vec<lsp::InlayHint>>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::inlay_hints(s, &params.text_document.uri, params.range, encoding)).await
    }

    async fn signature_help(&self, params: lsp::SignatureHelpParams) -> Result<Option<lsp::SignatureHelp>> {
        let encoding = self.encoding();
        let at = params.text_document_position_params;
        self.on_snapshot(move |s| handlers::signature_help(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn formatting(&self, params: lsp::DocumentFormattingParams) -> Result<Option<Vec<lsp::TextEdit>>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::formatting(s, &params.text_document.uri, encoding)).await
    }

    async fn references(&self, params: lsp::ReferenceParams) -> Result<Option<Vec<lsp::Location>>> {
        let encoding = self.encoding();
        let at = params.text_document_position;
        let include = params.context.include_declaration;
        self.on_snapshot(move |s| handlers::references(s, &at.text_document.uri, at.position, include, encoding)).await
    }

    async fn document_highlight(
        &self,
        params: lsp::DocumentHighlightParams,
    ) -> Result<Option<Vec<lsp::DocumentHighlight>>> {
        let encoding = self.encoding();
        let at = params.text_document_position_params;
        self.on_snapshot(move |s| handlers::document_highlight(s, &at.text_document.uri, at.position, encoding)).await
    }

    async fn prepare_rename(
        &self,
        params: lsp::TextDocumentPositionParams,
    ) -> Result<Option<lsp::PrepareRenameResponse>> {
        let encoding = self.encoding();
        self.on_snapshot(move |s| handlers::prepare_rename(s, &params.text_document.uri, params.position, encoding))
            .await?
            .map_err(invalid_request)
    }

    async fn rename(&self, params: lsp::RenameParams) -> Result<Option<lsp::WorkspaceEdit>> {
        let encoding = self.encoding();
        let at = params.text_document_position;
        let new_name = params.new_name;
        self.on_snapshot(move |s| handlers::rename(s, &at.text_document.uri, at.position, &new_name, encoding))
            .await?
            .map_err(invalid_request)
    }
}

/// A request the server refuses, with the reason for the user.
fn invalid_request(message: String) -> Error {
    Error { code: ErrorCode::InvalidRequest, message: message.into(), data: None }
}
