//! Model → LSP: byte offsets to positions in the negotiated encoding, and every answer of the
//! model to its LSP type. Nothing else in the server builds an LSP position.

use std::collections::HashMap;

use gudsl_model::{
    hir::{Diagnostic, Severity},
    ide,
    syntax::{TextRange, TextSize},
    text::{ColumnUnit, LineIndex},
    Cancellable, FileId,
};
use tower_lsp_server::ls_types as lsp;

use super::{capabilities::Encoding, host::Snapshot};

pub fn position(index: &LineIndex, offset: TextSize, encoding: Encoding) -> lsp::Position {
    let at = index.line_col(offset, encoding.0);
    lsp::Position::new(at.line, at.col)
}

/// `path:line:column` (1-based, columns in the negotiated encoding) of a range's start, for
/// messages.
pub fn place(path: &str, index: &LineIndex, range: TextRange, encoding: Encoding) -> String {
    let at = position(index, range.start(), encoding);
    format!("{path}:{}:{}", at.line + 1, at.character + 1)
}

pub fn range(index: &LineIndex, range: TextRange, encoding: Encoding) -> lsp::Range {
    lsp::Range::new(position(index, range.start(), encoding), position(index, range.end(), encoding))
}

/// A place in some file of the workspace; `None` for a file the client has no URI for.
pub fn location(snap: &Snapshot, file: FileId, at: TextRange) -> Cancellable<Option<lsp::Location>> {
    let index = snap.analysis.line_index(file)?;
    Ok(snap.uri_of(file).map(|uri| lsp::Location { uri, range: range(index, at, snap.encoding) }))
}

/// Edits of several files, grouped by document.
pub fn workspace_edit(snap: &Snapshot, edits: Vec<(ide::FileRange, String)>) -> Cancellable<lsp::WorkspaceEdit> {
    let mut changes: HashMap<lsp::Uri, Vec<lsp::TextEdit>> = HashMap::new();
    for (place, new_text) in edits {
        let Some(uri) = snap.uri_of(place.file) else { continue };
        let index = snap.analysis.line_index(place.file)?;
        changes
            .entry(uri)
            .or_default()
            .push(lsp::TextEdit { range: range(index, place.range, snap.encoding), new_text });
    }
    Ok(lsp::WorkspaceEdit { changes: Some(changes), ..Default::default() })
}

/// A diagnostic of a document; its related places (the first declaration of a duplicate) are
/// located in whichever document holds them.
pub fn diagnostic(snap: &Snapshot, index: &LineIndex, d: &Diagnostic) -> lsp::Diagnostic {
    let encoding = snap.encoding;
    let related: Vec<lsp::DiagnosticRelatedInformation> = d
        .related
        .iter()
        .filter_map(|r| {
            let uri = snap.uri_of(r.file)?;
            let index = snap.analysis.line_index(r.file).ok()?;
            Some(lsp::DiagnosticRelatedInformation {
                location: lsp::Location { uri, range: range(index, r.range, encoding) },
                message: r.message.clone(),
            })
        })
        .collect();
    lsp::Diagnostic {
        related_information: (!related.is_empty()).then_some(related),
        range: range(index, d.range, encoding),
        severity: Some(match d.severity {
            Severity::Error => lsp::DiagnosticSeverity::ERROR,
            Severity::Warning => lsp::DiagnosticSeverity::WARNING,
        }),
        code: Some(lsp::NumberOrString::String(d.code.as_str().to_string())),
        source: Some("gudsl".to_string()),
        message: d.message.clone(),
        ..Default::default()
    }
}

#[allow(deprecated)] // `deprecated` is a required field of the LSP type.
/// A symbol and its children; `checkpoint` runs before each (it stops a conversion that a newer
/// edit made moot).
pub fn document_symbol(
    index: &LineIndex,
    symbol: ide::Symbol,
    encoding: Encoding,
    checkpoint: &dyn Fn() -> Cancellable<()>,
) -> Cancellable<lsp::DocumentSymbol> {
    checkpoint()?;
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
    let children = symbol
        .children
        .into_iter()
        .map(|c| document_symbol(index, c, encoding, checkpoint))
        .collect::<Cancellable<_>>()?;
    Ok(lsp::DocumentSymbol {
        name: symbol.name,
        detail: symbol.detail,
        kind,
        tags: None,
        deprecated: None,
        range: range(index, symbol.range, encoding),
        selection_range: range(index, symbol.selection_range, encoding),
        children: Some(children),
    })
}

#[allow(deprecated)] // `deprecated` is a required field of the LSP type.
pub fn workspace_symbol(snap: &Snapshot, symbol: ide::WorkspaceSymbol) -> Cancellable<Option<lsp::SymbolInformation>> {
    use ide::WorkspaceSymbolKind as K;
    let Some(location) = location(snap, symbol.file, symbol.focus_range)? else { return Ok(None) };
    Ok(Some(lsp::SymbolInformation {
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
        location,
        container_name: symbol.fqn.rsplit_once('.').map(|(container, _)| container.to_string()),
    }))
}

pub fn folding_range(index: &LineIndex, fold: ide::Fold, encoding: Encoding) -> lsp::FoldingRange {
    let lines = range(index, fold.range, encoding);
    lsp::FoldingRange {
        start_line: lines.start.line,
        start_character: None,
        end_line: lines.end.line,
        end_character: None,
        kind: Some(match fold.kind {
            ide::FoldKind::Region => lsp::FoldingRangeKind::Region,
            ide::FoldKind::Comment => lsp::FoldingRangeKind::Comment,
            ide::FoldKind::Imports => lsp::FoldingRangeKind::Imports,
        }),
        collapsed_text: None,
    }
}

/// A selection range chain, outermost last; an empty chain selects the position itself.
pub fn selection_range(
    index: &LineIndex,
    ranges: &[TextRange],
    at: lsp::Position,
    encoding: Encoding,
) -> lsp::SelectionRange {
    let mut selection: Option<lsp::SelectionRange> = None;
    for r in ranges.iter().rev() {
        selection = Some(lsp::SelectionRange { range: range(index, *r, encoding), parent: selection.map(Box::new) });
    }
    selection.unwrap_or(lsp::SelectionRange { range: lsp::Range::new(at, at), parent: None })
}

pub fn hover(index: &LineIndex, at: TextRange, markdown: String, encoding: Encoding) -> lsp::Hover {
    lsp::Hover {
        contents: lsp::HoverContents::Markup(lsp::MarkupContent { kind: lsp::MarkupKind::Markdown, value: markdown }),
        range: Some(range(index, at, encoding)),
    }
}

pub fn completion_item(item: ide::CompletionItem) -> lsp::CompletionItem {
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
    let format =
        if item.snippet.is_some() { lsp::InsertTextFormat::SNIPPET } else { lsp::InsertTextFormat::PLAIN_TEXT };
    // Names in scope sort before the types of other diagrams.
    let sort_text = Some(format!("{}{}", u8::from(item.far), item.label));
    lsp::CompletionItem {
        sort_text,
        label: item.label,
        kind: Some(kind),
        detail: item.detail,
        insert_text: item.snippet,
        insert_text_format: Some(format),
        ..Default::default()
    }
}

pub fn signature_help(help: ide::SignatureHelp) -> lsp::SignatureHelp {
    let parameters = help
        .parameters
        .into_iter()
        .map(|p| lsp::ParameterInformation { label: lsp::ParameterLabel::Simple(p), documentation: None })
        .collect();
    lsp::SignatureHelp {
        signatures: vec![lsp::SignatureInformation {
            label: help.label,
            documentation: None,
            parameters: Some(parameters),
            active_parameter: Some(help.active_parameter as u32),
        }],
        active_signature: Some(0),
        active_parameter: Some(help.active_parameter as u32),
    }
}

pub fn inlay_hint(index: &LineIndex, hint: ide::InlayHint, encoding: Encoding) -> lsp::InlayHint {
    lsp::InlayHint {
        position: position(index, hint.offset, encoding),
        label: lsp::InlayHintLabel::String(hint.label),
        kind: Some(lsp::InlayHintKind::PARAMETER),
        text_edits: None,
        tooltip: None,
        padding_left: None,
        padding_right: Some(true),
        data: None,
    }
}

pub fn code_action(snap: &Snapshot, index: &LineIndex, fix: ide::QuickFix) -> Cancellable<lsp::CodeActionOrCommand> {
    let diagnostic = lsp::Diagnostic {
        range: range(index, fix.diagnostic_range, snap.encoding),
        code: Some(lsp::NumberOrString::String(fix.code.as_str().to_string())),
        source: Some("gudsl".into()),
        ..Default::default()
    };
    Ok(lsp::CodeActionOrCommand::CodeAction(lsp::CodeAction {
        title: fix.title,
        kind: Some(lsp::CodeActionKind::QUICKFIX),
        diagnostics: Some(vec![diagnostic]),
        edit: Some(workspace_edit(snap, fix.edits)?),
        ..Default::default()
    }))
}

/// Semantic tokens in LSP's relative encoding (a token spanning lines is split per line, line
/// terminators left out); a
/// token's type is its `ide::TokenClass` as an index into `capabilities::semantic_token_legend`.
pub fn semantic_token_data(
    text: &str,
    index: &LineIndex,
    tokens: &[ide::HighlightedToken],
    encoding: Encoding,
    checkpoint: &dyn Fn() -> Cancellable<()>,
) -> Cancellable<Vec<u32>> {
    let mut data = Vec::new();
    let (mut last_line, mut last_col) = (0u32, 0u32);
    for token in tokens {
        checkpoint()?;
        let kind = token.class as u32;
        let modifiers = u32::from(token.declaration);
        for piece in index.lines_of(token.range) {
            let piece_text = &text[piece];
            let at = position(index, piece.start(), encoding);
            let length = match encoding.0 {
                ColumnUnit::Utf8 => piece_text.len() as u32,
                _ => piece_text.encode_utf16().count() as u32,
            };
            if length > 0 {
                let delta_line = at.line - last_line;
                let delta_col = if delta_line == 0 { at.character - last_col } else { at.character };
                data.extend([delta_line, delta_col, length, kind, modifiers]);
                last_line = at.line;
                last_col = at.character;
            }
        }
    }
    Ok(data)
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

/// Every token of `data` as one list (a full answer).
pub fn semantic_tokens(data: &[u32]) -> Vec<lsp::SemanticToken> {
    semantic_token_edit(&[], data).pop().and_then(|e| e.data).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use gudsl_model::text::ColumnUnit;

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

    #[test]
    fn a_token_over_crlf_and_lone_cr_lines_is_split_without_its_terminators() {
        let text = "x /* ab\r\ncd\ref */";
        let index = LineIndex::new(text);
        let comment = ide::HighlightedToken {
            range: TextRange::new(2.into(), (text.len() as u32).into()),
            class: ide::TokenClass::Comment,
            declaration: false,
        };
        let data = semantic_token_data(text, &index, &[comment], Encoding(ColumnUnit::Utf16), &|| Ok(())).unwrap();
        let class = ide::TokenClass::Comment as u32;
        // `/* ab` on line 0 from column 2, `cd` on line 1, `ef */` on line 2.
        assert_eq!(data, [0, 2, 5, class, 0, 1, 0, 2, class, 0, 1, 0, 5, class, 0]);
    }

    #[test]
    fn utf16_and_utf8_positions_round_trip_outside_the_bmp() {
        let text = "// 😀 ä\nClassDiagram X { }\n";
        let index = LineIndex::new(text);
        let x = TextSize::from(text.find('X').unwrap() as u32);
        for encoding in [Encoding(ColumnUnit::Utf8), Encoding(ColumnUnit::Utf16)] {
            let at = position(&index, x, encoding);
            assert_eq!(super::super::from_proto::offset(&index, at, encoding), x);
        }
        let after_emoji = TextSize::from(text.find(" ä").unwrap() as u32);
        assert_eq!(position(&index, after_emoji, Encoding(ColumnUnit::Utf16)), lsp::Position::new(0, 5));
        assert_eq!(position(&index, after_emoji, Encoding(ColumnUnit::Utf8)), lsp::Position::new(0, 7));
    }
}
