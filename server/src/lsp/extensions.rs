//! The handlers of gudsl's own requests (`ext.rs`, `docs/protocol.md`): `gudsl/viewFileText`,
//! `gudsl/diagrams`, `gudsl/graph` and `gudsl/applyGraphEdit` (with the `gudsl/graphChanged`
//! it sends when positions change), `gudsl/parameters` and `gudsl/setParameter`, and the
//! cancel of a run's progress.

use tower_lsp_server::{jsonrpc::Result, ls_types as lsp};

use super::{
    ext::{self, GraphChanged, GraphChangedNotification},
    graph, graph_edit, invalid_params, lock, parameters, request_failed,
    server::Backend,
    wgsl,
};

impl Backend {
    /// `gudsl/viewFileText`: the text the server has for a document, to compare with the
    /// editor's (as rust-analyzer's `viewFileText`), or of a read-only document it makes (the
    /// bundled library, generated WGSL); `null` for a document it does not know.
    pub async fn view_file_text(&self, params: lsp::TextDocumentIdentifier) -> Result<Option<String>> {
        if let Some(diagram) = wgsl::diagram_of(params.uri.as_str()).map(str::to_string) {
            return self.on_snapshot(move |s| wgsl::generated(s, &diagram)).await?.map(Some).map_err(request_failed);
        }
        Ok(lock(&self.host).text(&params.uri).map(str::to_string))
    }

    /// `gudsl/diagrams`: a document's diagrams (`docs/protocol.md`); `null` for a document the
    /// server does not know.
    pub async fn diagrams(&self, params: ext::DiagramsParams) -> Result<Option<ext::Diagrams>> {
        self.on_snapshot(move |s| graph::diagrams(s, &params)).await
    }

    /// `gudsl/graph`: one diagram as a laid-out graph (`docs/protocol.md`).
    pub async fn graph(&self, params: ext::GraphParams) -> Result<ext::GraphView> {
        let scenes = self.scenes.clone();
        self.on_snapshot(move |s| graph::graph(s, &params, &scenes)).await?.map_err(invalid_params)
    }

    /// `gudsl/applyGraphEdit`: operations on a diagram's graph as text edits (`docs/protocol.md`).
    pub async fn apply_graph_edit(&self, params: ext::GraphEditParams) -> Result<ext::GraphEditAnswer> {
        let scenes = self.scenes.clone();
        let uri = params.text_document.uri.clone();
        let version = params.text_document.version;
        let answer = self.on_snapshot(move |s| graph_edit::apply_graph_edit(s, &params, &scenes)).await?;
        let answer = answer.map_err(request_failed)?;
        // Positions publish no diagnostics: say so.
        if let Some(written) = &answer.layout {
            let changed = GraphChanged { uri, version, diagrams: vec![written.diagram.clone()] };
            self.client.send_notification::<GraphChangedNotification>(changed).await;
        }
        Ok(answer)
    }

    /// `gudsl/parameters`: an instance's parameters for a panel's controls.
    pub async fn parameters(&self, params: ext::ParametersParams) -> Result<ext::Parameters> {
        self.on_snapshot(move |s| parameters::parameters(s, &params)).await?.map_err(invalid_params)
    }

    /// `gudsl/setParameter`: the edit that sets a parameter, for the client to apply.
    pub async fn set_parameter(&self, params: ext::SetParameterParams) -> Result<lsp::WorkspaceEdit> {
        self.on_snapshot(move |s| parameters::set_parameter(s, &params)).await?.map_err(request_failed)
    }

    /// `window/workDoneProgress/cancel`: stops the run reporting under the token (between
    /// nodes); other tokens are ignored.
    pub async fn work_done_progress_cancel(&self, params: lsp::WorkDoneProgressCancelParams) {
        self.runs.cancel(&params.token);
    }
}
