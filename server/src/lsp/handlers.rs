//! Request handlers: one function per LSP feature, each on a snapshot, converting the model's
//! answer to LSP types.

use gudsl_model::{
    db::line_index,
    hir::{file_diagnostics, Severity},
    ide,
};
use tower_lsp_server::ls_types as lsp;

use super::{
    convert::Encoding,
    host::{Host, Snapshot},
};

pub fn diagnostics(snapshot: &Snapshot, file: gudsl_model::db::SourceFile, encoding: Encoding) -> Vec<lsp::Diagnostic> {
    let index = line_index(&snapshot.db, file);
    file_diagnostics(&snapshot.db, snapshot.workspace, file)
        .iter()
        .map(|d| lsp::Diagnostic {
            range: encoding.range(index, d.range),
            severity: Some(match d.severity {
                Severity::Error => lsp::DiagnosticSeverity::ERROR,
                Severity::Warning => lsp::DiagnosticSeverity::WARNING,
            }),
            code: Some(lsp::NumberOrString::String(d.code.as_str().to_string())),
            source: Some("gudsl".to_string()),
            message: d.message.clone(),
            ..Default::default()
        })
        .collect()
}

pub fn document_symbols(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    encoding: Encoding,
) -> Option<lsp::DocumentSymbolResponse> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let tree = gudsl_model::db::parse(&snapshot.db, file).source_file();
    #[allow(deprecated)] // `deprecated` is a required field of the LSP type.
    fn convert(symbol: ide::Symbol, index: &gudsl_model::text::LineIndex, encoding: Encoding) -> lsp::DocumentSymbol {
        use ide::SymbolKind as K;
        let kind = match symbol.kind {
            K::Diagram => lsp::SymbolKind::NAMESPACE,
            K::Class => lsp::SymbolKind::CLASS,
            K::Interface => lsp::SymbolKind::INTERFACE,
            K::Enum => lsp::SymbolKind::ENUM,
            K::EnumValue => lsp::SymbolKind::ENUM_MEMBER,
            K::Attribute => lsp::SymbolKind::STRUCT,
            K::Field => lsp::SymbolKind::FIELD,
            K::Method => lsp::SymbolKind::METHOD,
            K::Variable => lsp::SymbolKind::VARIABLE,
            K::Swimlane => lsp::SymbolKind::MODULE,
            K::Node => lsp::SymbolKind::FUNCTION,
            K::Component => lsp::SymbolKind::OBJECT,
            K::Port => lsp::SymbolKind::INTERFACE,
            K::Instance => lsp::SymbolKind::OBJECT,
        };
        lsp::DocumentSymbol {
            name: symbol.name,
            detail: symbol.detail,
            kind,
            tags: None,
            deprecated: None,
            range: encoding.range(index, symbol.range),
            selection_range: encoding.range(index, symbol.selection_range),
            children: Some(symbol.children.into_iter().map(|c| convert(c, index, encoding)).collect()),
        }
    }
    let symbols = ide::document_symbols(&tree).into_iter().map(|s| convert(s, index, encoding)).collect();
    Some(lsp::DocumentSymbolResponse::Nested(symbols))
}

/// Navigation targets as LSP locations; `None` when there are none.
fn navigation(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
    find: fn(
        &dyn gudsl_model::db::Db,
        gudsl_model::db::Workspace,
        gudsl_model::db::SourceFile,
        gudsl_model::syntax::TextSize,
    ) -> Vec<ide::NavigationTarget>,
) -> Option<lsp::GotoDefinitionResponse> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let locations: Vec<lsp::Location> = find(&snapshot.db, snapshot.workspace, file, offset)
        .into_iter()
        .filter_map(|target| {
            let index = line_index(&snapshot.db, target.file);
            Some(lsp::Location { uri: snapshot.uri_of(target.file)?, range: encoding.range(index, target.focus_range) })
        })
        .collect();
    (!locations.is_empty()).then_some(lsp::GotoDefinitionResponse::Array(locations))
}

pub fn goto_definition(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<lsp::GotoDefinitionResponse> {
    navigation(snapshot, uri, position, encoding, ide::goto_definition)
}

pub fn goto_type_definition(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<lsp::GotoDefinitionResponse> {
    navigation(snapshot, uri, position, encoding, ide::goto_type_definition)
}

pub fn hover(snapshot: &Snapshot, uri: &lsp::Uri, position: lsp::Position, encoding: Encoding) -> Option<lsp::Hover> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let (range, markdown) = ide::hover(&snapshot.db, snapshot.workspace, file, offset)?;
    let index = line_index(&snapshot.db, file);
    Some(lsp::Hover {
        contents: lsp::HoverContents::Markup(lsp::MarkupContent { kind: lsp::MarkupKind::Markdown, value: markdown }),
        range: Some(encoding.range(index, range)),
    })
}

pub fn folding_ranges(snapshot: &Snapshot, uri: &lsp::Uri, encoding: Encoding) -> Option<Vec<lsp::FoldingRange>> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let root = gudsl_model::db::parse(&snapshot.db, file).syntax_node();
    Some(
        ide::folding_ranges(&root, index)
            .into_iter()
            .map(|fold| {
                let range = encoding.range(index, fold.range);
                lsp::FoldingRange {
                    start_line: range.start.line,
                    start_character: None,
                    end_line: range.end.line,
                    end_character: None,
                    kind: Some(match fold.kind {
                        ide::FoldKind::Region => lsp::FoldingRangeKind::Region,
                        ide::FoldKind::Comment => lsp::FoldingRangeKind::Comment,
                        ide::FoldKind::Imports => lsp::FoldingRangeKind::Imports,
                    }),
                    collapsed_text: None,
                }
            })
            .collect(),
    )
}

pub fn references(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    include_declaration: bool,
    encoding: Encoding,
) -> Option<Vec<lsp::Location>> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let refs = ide::find_references(&snapshot.db, snapshot.workspace, file, offset, include_declaration);
    Some(
        refs.into_iter()
            .filter_map(|r| {
                let index = line_index(&snapshot.db, r.file);
                Some(lsp::Location { uri: snapshot.uri_of(r.file)?, range: encoding.range(index, r.range) })
            })
            .collect(),
    )
}

pub fn document_highlight(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<Vec<lsp::DocumentHighlight>> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let index = line_index(&snapshot.db, file);
    let refs = ide::find_references(&snapshot.db, snapshot.workspace, file, offset, true);
    Some(
        refs.into_iter()
            .filter(|r| r.file == file)
            .map(|r| lsp::DocumentHighlight { range: encoding.range(index, r.range), kind: None })
            .collect(),
    )
}

pub fn prepare_rename(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Result<Option<lsp::PrepareRenameResponse>, String> {
    let Some(document) = snapshot.document(uri) else { return Ok(None) };
    let offset = Host::offset(snapshot, document.file, position, encoding);
    let index = line_index(&snapshot.db, document.file);
    match ide::prepare_rename(&snapshot.db, snapshot.workspace, document.file, offset) {
        Ok(range) => Ok(Some(lsp::PrepareRenameResponse::Range(encoding.range(index, range)))),
        Err(error) => Err(error.0),
    }
}

pub fn rename(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    new_name: &str,
    encoding: Encoding,
) -> Result<Option<lsp::WorkspaceEdit>, String> {
    let Some(document) = snapshot.document(uri) else { return Ok(None) };
    let offset = Host::offset(snapshot, document.file, position, encoding);
    let edits = ide::rename(&snapshot.db, snapshot.workspace, document.file, offset, new_name).map_err(|e| e.0)?;
    let mut changes: std::collections::HashMap<lsp::Uri, Vec<lsp::TextEdit>> = std::collections::HashMap::new();
    for (place, text) in edits {
        let Some(uri) = snapshot.uri_of(place.file) else { continue };
        let index = line_index(&snapshot.db, place.file);
        changes
            .entry(uri)
            .or_default()
            .push(lsp::TextEdit { range: encoding.range(index, place.range), new_text: text });
    }
    Ok(Some(lsp::WorkspaceEdit { changes: Some(changes), ..Default::default() }))
}

/// The whole document formatted, as one edit (none if it is formatted or has syntax errors).
pub fn formatting(snapshot: &Snapshot, uri: &lsp::Uri, encoding: Encoding) -> Option<Vec<lsp::TextEdit>> {
    let file = snapshot.document(uri)?.file;
    let text = file.text(&snapshot.db);
    let formatted = gudsl_model::format::format(gudsl_model::db::parse(&snapshot.db, file))?;
    if &formatted == text {
        return Some(Vec::new());
    }
    let index = line_index(&snapshot.db, file);
    let whole = gudsl_model::syntax::TextRange::up_to((text.len() as u32).into());
    Some(vec![lsp::TextEdit { range: encoding.range(index, whole), new_text: formatted }])
}

pub fn completion(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<lsp::CompletionResponse> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let items = ide::completions(&snapshot.db, snapshot.workspace, file, offset)
        .into_iter()
        .map(|item| {
            use ide::CompletionKind as K;
            let kind = match item.kind {
                K::Keyword => lsp::CompletionItemKind::KEYWORD,
                K::Snippet => lsp::CompletionItemKind::SNIPPET,
                K::Type => lsp::CompletionItemKind::CLASS,
                K::Namespace => lsp::CompletionItemKind::MODULE,
                K::Node => lsp::CompletionItemKind::FUNCTION,
                K::Field => lsp::CompletionItemKind::FIELD,
                K::Method => lsp::CompletionItemKind::METHOD,
                K::Variable => lsp::CompletionItemKind::VARIABLE,
                K::Interface => lsp::CompletionItemKind::INTERFACE,
                K::EnumValue => lsp::CompletionItemKind::ENUM_MEMBER,
            };
            let is_snippet = item.snippet.is_some();
            lsp::CompletionItem {
                label: item.label.clone(),
                kind: Some(kind),
                detail: item.detail,
                insert_text: item.snippet,
                insert_text_format: Some(if is_snippet {
                    lsp::InsertTextFormat::SNIPPET
                } else {
                    lsp::InsertTextFormat::PLAIN_TEXT
                }),
                ..Default::default()
            }
        })
        .collect();
    Some(lsp::CompletionResponse::Array(items))
}

pub fn selection_ranges(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    positions: &[lsp::Position],
    encoding: Encoding,
) -> Option<Vec<lsp::SelectionRange>> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let root = gudsl_model::db::parse(&snapshot.db, file).syntax_node();
    Some(
        positions
            .iter()
            .map(|&position| {
                let offset = Host::offset(snapshot, file, position, encoding);
                let ranges = ide::selection_ranges(&root, offset);
                // Outermost first, each the parent of the next.
                let mut selection: Option<lsp::SelectionRange> = None;
                for range in ranges.iter().rev() {
                    selection = Some(lsp::SelectionRange {
                        range: encoding.range(index, *range),
                        parent: selection.map(Box::new),
                    });
                }
                selection.unwrap_or(lsp::SelectionRange { range: lsp::Range::new(position, position), parent: None })
            })
            .collect(),
    )
}

#[allow(deprecated)] // `deprecated` is a required field of the LSP type.
pub fn workspace_symbols(snapshot: &Snapshot, query: &str, encoding: Encoding) -> Vec<lsp::SymbolInformation> {
    ide::workspace_symbols(&snapshot.db, snapshot.workspace, query, 500)
        .into_iter()
        .filter_map(|symbol| {
            use ide::WorkspaceSymbolKind as K;
            let index = line_index(&snapshot.db, symbol.file);
            Some(lsp::SymbolInformation {
                name: symbol.name,
                kind: match symbol.kind {
                    K::Diagram => lsp::SymbolKind::NAMESPACE,
                    K::Activity => lsp::SymbolKind::FUNCTION,
                    K::Class => lsp::SymbolKind::CLASS,
                    K::Interface => lsp::SymbolKind::INTERFACE,
                    K::Enum => lsp::SymbolKind::ENUM,
                    K::Attribute => lsp::SymbolKind::STRUCT,
                },
                tags: None,
                deprecated: None,
                location: lsp::Location {
                    uri: snapshot.uri_of(symbol.file)?,
                    range: encoding.range(index, symbol.focus_range),
                },
                container_name: symbol.fqn.rsplit_once('.').map(|(container, _)| container.to_string()),
            })
        })
        .collect()
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

/// The semantic tokens of a document in LSP's relative encoding (multi-line tokens split).
pub fn semantic_token_data(snapshot: &Snapshot, uri: &lsp::Uri, encoding: Encoding) -> Option<Vec<u32>> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let text = file.text(&snapshot.db);
    let mut data = Vec::new();
    let (mut last_line, mut last_col) = (0u32, 0u32);
    for token in ide::semantic_tokens(&snapshot.db, file) {
        let kind = token.class as u32;
        let modifiers = u32::from(token.declaration);
        let start: usize = token.range.start().into();
        let end: usize = token.range.end().into();
        // One entry per line of the token.
        let mut line_start = start;
        for piece in text[start..end].split_inclusive('\n') {
            let piece_text = piece.trim_end_matches(['\n', '\r']);
            let from = gudsl_model::syntax::TextSize::from(line_start as u32);
            let position = encoding.position(index, from);
            let length = match encoding.0 {
                gudsl_model::text::ColumnUnit::Utf8 => piece_text.len() as u32,
                _ => piece_text.encode_utf16().count() as u32,
            };
            if length > 0 {
                let delta_line = position.line - last_line;
                let delta_col = if delta_line == 0 { position.character - last_col } else { position.character };
                data.extend([delta_line, delta_col, length, kind, modifiers]);
                last_line = position.line;
                last_col = position.character;
            }
            line_start += piece.len();
        }
    }
    Some(data)
}

/// The edit that turns `old` token data into `new` (common prefix and suffix kept).
pub fn semantic_token_edit(old: &[u32], new: &[u32]) -> Vec<lsp::SemanticTokensEdit> {
    // Edits replace whole tokens (five numbers each).
    let prefix = old.iter().zip(new).take_while(|(a, b)| a == b).count() / 5 * 5;
    let suffix = old[prefix..].iter().rev().zip(new[prefix..].iter().rev()).take_while(|(a, b)| a == b).count() / 5 * 5;
    let delete = old.len() - prefix - suffix;
    let insert = &new[prefix..new.len() - suffix];
    if delete == 0 && insert.is_empty() {
        return Vec::new();
    }
    let data: Vec<lsp::SemanticToken> = insert
        .chunks(5)
        .map(|c| lsp::SemanticToken {
            delta_line: c[0],
            delta_start: c[1],
            length: c[2],
            token_type: c[3],
            token_modifiers_bitset: c[4],
        })
        .collect();
    vec![lsp::SemanticTokensEdit { start: prefix as u32, delete_count: delete as u32, data: Some(data) }]
}

pub fn code_actions(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    range: lsp::Range,
    encoding: Encoding,
) -> Option<Vec<lsp::CodeActionOrCommand>> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let text_len = file.text(&snapshot.db).len();
    let start = encoding.offset(index, text_len, range.start);
    let end = encoding.offset(index, text_len, range.end);
    let range = gudsl_model::syntax::TextRange::new(start.min(end), end.max(start));
    let fixes = ide::quick_fixes(&snapshot.db, snapshot.workspace, file, range);
    Some(
        fixes
            .into_iter()
            .map(|fix| {
                let mut changes: std::collections::HashMap<lsp::Uri, Vec<lsp::TextEdit>> =
                    std::collections::HashMap::new();
                for (place, text) in fix.edits {
                    if let Some(uri) = snapshot.uri_of(place.file) {
                        let index = line_index(&snapshot.db, place.file);
                        changes
                            .entry(uri)
                            .or_default()
                            .push(lsp::TextEdit { range: encoding.range(index, place.range), new_text: text });
                    }
                }
                lsp::CodeActionOrCommand::CodeAction(lsp::CodeAction {
                    title: fix.title,
                    kind: Some(lsp::CodeActionKind::QUICKFIX),
                    diagnostics: Some(vec![lsp::Diagnostic {
                        range: encoding.range(index, fix.diagnostic_range),
                        code: Some(lsp::NumberOrString::String(fix.code.as_str().to_string())),
                        source: Some("gudsl".into()),
                        ..Default::default()
                    }]),
                    edit: Some(lsp::WorkspaceEdit { changes: Some(changes), ..Default::default() }),
                    ..Default::default()
                })
            })
            .collect(),
    )
}

pub fn inlay_hints(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    range: lsp::Range,
    encoding: Encoding,
) -> Option<Vec<lsp::InlayHint>> {
    let file = snapshot.document(uri)?.file;
    let index = line_index(&snapshot.db, file);
    let len = file.text(&snapshot.db).len();
    let (start, end) = (encoding.offset(index, len, range.start), encoding.offset(index, len, range.end));
    let range = gudsl_model::syntax::TextRange::new(start.min(end), end.max(start));
    Some(
        ide::inlay_hints(&snapshot.db, file, range)
            .into_iter()
            .map(|hint| lsp::InlayHint {
                position: encoding.position(index, hint.offset),
                label: lsp::InlayHintLabel::String(hint.label),
                kind: Some(lsp::InlayHintKind::PARAMETER),
                text_edits: None,
                tooltip: None,
                padding_left: None,
                padding_right: Some(true),
                data: None,
            })
            .collect(),
    )
}

pub fn signature_help(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<lsp::SignatureHelp> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let help = ide::signature_help(&snapshot.db, snapshot.workspace, file, offset)?;
    Some(lsp::SignatureHelp {
        signatures: vec![lsp::SignatureInformation {
            label: help.label,
            documentation: None,
            parameters: Some(
                help.parameters
                    .into_iter()
                    .map(|p| lsp::ParameterInformation { label: lsp::ParameterLabel::Simple(p), documentation: None })
                    .collect(),
            ),
            active_parameter: Some(help.active_parameter as u32),
        }],
        active_signature: Some(0),
        active_parameter: Some(help.active_parameter as u32),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn semantic_token_edits_keep_common_prefix_and_suffix() {
        let old = [0, 0, 5, 0, 0, 1, 2, 3, 1, 0, 0, 4, 2, 2, 0];
        let mut new = old.to_vec();
        new[7] = 9; // one token's length changed
        let edits = semantic_token_edit(&old, &new);
        assert_eq!(edits.len(), 1);
        assert_eq!((edits[0].start, edits[0].delete_count), (5, 5));
        assert_eq!(edits[0].data.as_ref().unwrap()[0].length, 9);
        assert!(semantic_token_edit(&old, &old).is_empty());
        let all = semantic_token_edit(&[], &old);
        assert_eq!(all[0].data.as_ref().unwrap().len(), 3);
    }
}
