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

pub fn goto_definition(
    snapshot: &Snapshot,
    uri: &lsp::Uri,
    position: lsp::Position,
    encoding: Encoding,
) -> Option<lsp::GotoDefinitionResponse> {
    let file = snapshot.document(uri)?.file;
    let offset = Host::offset(snapshot, file, position, encoding);
    let locations: Vec<lsp::Location> = ide::goto_definition(&snapshot.db, snapshot.workspace, file, offset)
        .into_iter()
        .filter_map(|target| {
            let index = line_index(&snapshot.db, target.file);
            Some(lsp::Location { uri: snapshot.uri_of(target.file)?, range: encoding.range(index, target.focus_range) })
        })
        .collect();
    (!locations.is_empty()).then_some(lsp::GotoDefinitionResponse::Array(locations))
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
