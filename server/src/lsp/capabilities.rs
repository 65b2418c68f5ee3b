//! What the server offers a client, and the position encoding negotiated at initialisation.

use gudsl_model::text::ColumnUnit;
use tower_lsp_server::ls_types as lsp;

use super::ext;

/// Positions in the encoding negotiated at initialisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Encoding(pub ColumnUnit);

impl Encoding {
    /// UTF-8 if the client offers it, else UTF-16 (the LSP default).
    pub fn negotiate(capabilities: &lsp::ClientCapabilities) -> Encoding {
        let offered = capabilities.general.as_ref().and_then(|g| g.position_encodings.as_ref());
        if offered.is_some_and(|kinds| kinds.contains(&lsp::PositionEncodingKind::UTF8)) {
            Encoding(ColumnUnit::Utf8)
        } else {
            Encoding(ColumnUnit::Utf16)
        }
    }

    pub fn kind(self) -> lsp::PositionEncodingKind {
        match self.0 {
            ColumnUnit::Utf8 => lsp::PositionEncodingKind::UTF8,
            ColumnUnit::Utf16 | ColumnUnit::Char => lsp::PositionEncodingKind::UTF16,
        }
    }
}

/// Every feature the server implements (the table in `server.rs` answers them).
pub fn server_capabilities(encoding: Encoding) -> lsp::ServerCapabilities {
    lsp::ServerCapabilities {
        position_encoding: Some(encoding.kind()),
        text_document_sync: Some(lsp::TextDocumentSyncCapability::Options(lsp::TextDocumentSyncOptions {
            open_close: Some(true),
            change: Some(lsp::TextDocumentSyncKind::INCREMENTAL),
            // Saving writes the diagrams' rows into the layout sidecar.
            save: Some(lsp::TextDocumentSyncSaveOptions::Supported(true)),
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
                legend: semantic_token_legend(),
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
        code_lens_provider: Some(lsp::CodeLensOptions { resolve_provider: Some(false) }),
        execute_command_provider: Some(lsp::ExecuteCommandOptions {
            commands: ext::COMMANDS.iter().map(|c| c.to_string()).collect(),
            work_done_progress_options: lsp::WorkDoneProgressOptions { work_done_progress: Some(true) },
        }),
        // The requests beyond LSP a client may send, and the notifications it may get
        // (`docs/protocol.md`).
        experimental: Some(serde_json::json!({
            "gudsl": { "requests": ext::REQUESTS, "notifications": ext::NOTIFICATIONS }
        })),
        ..Default::default()
    }
}

/// The token types of the semantic-token legend, in `ide::TokenClass` order.
pub fn semantic_token_legend() -> lsp::SemanticTokensLegend {
    use lsp::SemanticTokenType as T;
    lsp::SemanticTokensLegend {
        token_types: vec![
            T::KEYWORD,
            T::COMMENT,
            T::STRING,
            T::NUMBER,
            T::OPERATOR,
            T::NAMESPACE,
            T::CLASS,
            T::INTERFACE,
            T::ENUM,
            T::ENUM_MEMBER,
            T::TYPE,
            T::FUNCTION,
            T::METHOD,
            T::PROPERTY,
            T::PARAMETER,
            T::VARIABLE,
            T::DECORATOR,
        ],
        token_modifiers: vec![lsp::SemanticTokenModifier::DECLARATION],
    }
}
