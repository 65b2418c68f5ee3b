//! Request handlers, one a feature: the request's positions to the model's (`from_proto`), the
//! question to the snapshot's [`Analysis`](gudsl_model::Analysis), the answer back to LSP
//! (`to_proto`). A handler returns `Err(Cancelled)` when a newer edit made its answer moot.

use gudsl_host::{diagnostics::file_diagnostics, named::is_runnable};
use gudsl_model::{hir::DefKind, syntax::TextRange, Cancellable, FileId};
use tower_lsp_server::ls_types as lsp;

use super::{
    ext::{PREVIEW, RUN, RUN_PIPELINE, SHOW_WGSL},
    from_proto,
    host::Snapshot,
    to_proto,
};

/// The diagnostics to publish for a document: those `gudsl check` reports
/// (`gudsl_host::diagnostics`, the one place that decides them).
pub fn diagnostics(snap: &Snapshot, file: FileId) -> Cancellable<Vec<lsp::Diagnostic>> {
    let diagnostics = file_diagnostics(&snap.analysis, file, &snap.preparations)?;
    let index = snap.analysis.line_index(file)?;
    convert(snap, &diagnostics, |d| to_proto::diagnostic(snap, index, d))
}

/// Above each diagram of a document that can be run or generated: "▶ Run" for a host activity
/// diagram without parameters, "Show generated WGSL" for a device diagram, "▶ Run pipeline" and
/// "◉ Live preview" (on and off) for a component-instance diagram.
pub fn code_lenses(snap: &Snapshot, uri: &lsp::Uri) -> Cancellable<Option<Vec<lsp::CodeLens>>> {
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let lenses = snap.analysis.with_semantics(|sema| {
        let mut lenses = Vec::new();
        for def in sema.file_diagrams(file) {
            let (title, command) = if matches!(def.kind, DefKind::ComponentInstanceDiagram) {
                ("▶ Run pipeline", RUN_PIPELINE)
            } else if !matches!(def.kind, DefKind::Activity(_)) {
                continue;
            } else if gudsl_codegen::is_kernel(sema, def) {
                ("Show generated WGSL", SHOW_WGSL)
            } else if is_runnable(sema, def) {
                ("▶ Run", RUN)
            } else {
                continue;
            };
            let Some((_, name)) = sema.declaration(def) else { continue };
            lenses.push((name, title, command, def.fqn.clone()));
            if command == RUN_PIPELINE {
                lenses.push((name, "◉ Live preview", PREVIEW, def.fqn.clone()));
            }
        }
        lenses
    })?;
    let mut lenses: Vec<lsp::CodeLens> = lenses
        .into_iter()
        .map(|(name, title, command, diagram)| lsp::CodeLens {
            range: to_proto::range(index, name, snap.encoding),
            command: Some(lsp::Command {
                title: title.to_string(),
                command: command.to_string(),
                arguments: Some(vec![serde_json::json!({ "diagram": diagram })]),
            }),
            data: None,
        })
        .collect();
    lenses.sort_by_key(|lens| (lens.range.start.line, lens.range.start.character));
    Ok(Some(lenses))
}

/// Converts `items` one by one, stopping with `Cancelled` once a newer edit waits for the
/// snapshot: an answer of hundreds of thousands of items must not hold up typing.
fn convert<T, U>(
    snap: &Snapshot,
    items: impl IntoIterator<Item = T>,
    mut f: impl FnMut(T) -> U,
) -> Cancellable<Vec<U>> {
    items
        .into_iter()
        .map(|item| {
            snap.analysis.check_cancelled()?;
            Ok(f(item))
        })
        .collect()
}

pub fn document_symbols(snap: &Snapshot, uri: &lsp::Uri) -> Cancellable<Option<lsp::DocumentSymbolResponse>> {
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let symbols = snap.analysis.document_symbols(file)?;
    let checkpoint = || snap.analysis.check_cancelled();
    let symbols = symbols
        .into_iter()
        .map(|s| to_proto::document_symbol(index, s, snap.encoding, &checkpoint))
        .collect::<Cancellable<_>>()?;
    Ok(Some(lsp::DocumentSymbolResponse::Nested(symbols)))
}

/// Navigation targets as locations; `None` when there are none.
fn locations(
    snap: &Snapshot,
    targets: Vec<gudsl_model::ide::NavigationTarget>,
) -> Cancellable<Option<lsp::GotoDefinitionResponse>> {
    let mut found = Vec::new();
    for target in targets {
        found.extend(to_proto::location(snap, target.file, target.focus_range)?);
    }
    Ok((!found.is_empty()).then_some(lsp::GotoDefinitionResponse::Array(found)))
}

pub fn goto_definition(
    snap: &Snapshot,
    at: lsp::TextDocumentPositionParams,
) -> Cancellable<Option<lsp::GotoDefinitionResponse>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    locations(snap, snap.analysis.goto_definition(file, offset)?)
}

pub fn goto_type_definition(
    snap: &Snapshot,
    at: lsp::TextDocumentPositionParams,
) -> Cancellable<Option<lsp::GotoDefinitionResponse>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    locations(snap, snap.analysis.goto_type_definition(file, offset)?)
}

pub fn hover(snap: &Snapshot, at: lsp::TextDocumentPositionParams) -> Cancellable<Option<lsp::Hover>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    let Some((range, markdown)) = snap.analysis.hover(file, offset)? else { return Ok(None) };
    Ok(Some(to_proto::hover(snap.analysis.line_index(file)?, range, markdown, snap.encoding)))
}

pub fn folding_ranges(snap: &Snapshot, uri: &lsp::Uri) -> Cancellable<Option<Vec<lsp::FoldingRange>>> {
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let folds = snap.analysis.folding_ranges(file)?;
    Ok(Some(convert(snap, folds, |fold| to_proto::folding_range(index, fold, snap.encoding))?))
}

pub fn references(snap: &Snapshot, params: lsp::ReferenceParams) -> Cancellable<Option<Vec<lsp::Location>>> {
    let at = params.text_document_position;
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    let mut found = Vec::new();
    for reference in snap.analysis.find_references(file, offset, params.context.include_declaration)? {
        found.extend(to_proto::location(snap, reference.file, reference.range)?);
    }
    Ok(Some(found))
}

pub fn document_highlight(
    snap: &Snapshot,
    at: lsp::TextDocumentPositionParams,
) -> Cancellable<Option<Vec<lsp::DocumentHighlight>>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    let index = snap.analysis.line_index(file)?;
    let references = snap.analysis.find_references(file, offset, true)?;
    let here = references.into_iter().filter(|r| r.file == file);
    Ok(Some(convert(snap, here, |r| lsp::DocumentHighlight {
        range: to_proto::range(index, r.range, snap.encoding),
        kind: None,
    })?))
}

/// The range a rename would change, or why there is nothing to rename here.
pub fn prepare_rename(
    snap: &Snapshot,
    at: lsp::TextDocumentPositionParams,
) -> Cancellable<Result<Option<lsp::PrepareRenameResponse>, String>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(Ok(None));
    };
    let index = snap.analysis.line_index(file)?;
    Ok(match snap.analysis.prepare_rename(file, offset)? {
        Ok(range) => Ok(Some(lsp::PrepareRenameResponse::Range(to_proto::range(index, range, snap.encoding)))),
        Err(error) => Err(error.0),
    })
}

pub fn rename(snap: &Snapshot, params: lsp::RenameParams) -> Cancellable<Result<Option<lsp::WorkspaceEdit>, String>> {
    let at = params.text_document_position;
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(Ok(None));
    };
    Ok(match snap.analysis.rename(file, offset, &params.new_name)? {
        Ok(edits) => Ok(Some(to_proto::workspace_edit(snap, edits)?)),
        Err(error) => Err(error.0),
    })
}

/// The whole document formatted, as one edit (none if it is formatted or has syntax errors).
pub fn formatting(snap: &Snapshot, uri: &lsp::Uri) -> Cancellable<Option<Vec<lsp::TextEdit>>> {
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let Some(formatted) = snap.analysis.format(file)? else { return Ok(None) };
    let text = snap.analysis.file_text(file);
    if formatted == text {
        return Ok(Some(Vec::new()));
    }
    let whole = TextRange::up_to((text.len() as u32).into());
    let range = to_proto::range(snap.analysis.line_index(file)?, whole, snap.encoding);
    Ok(Some(vec![lsp::TextEdit { range, new_text: formatted }]))
}

pub fn completion(
    snap: &Snapshot,
    at: lsp::TextDocumentPositionParams,
) -> Cancellable<Option<lsp::CompletionResponse>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    let completions = snap.analysis.completions(file, offset)?;
    Ok(Some(lsp::CompletionResponse::List(lsp::CompletionList {
        is_incomplete: completions.incomplete,
        items: completions.items.into_iter().map(to_proto::completion_item).collect(),
    })))
}

pub fn selection_ranges(
    snap: &Snapshot,
    params: lsp::SelectionRangeParams,
) -> Cancellable<Option<Vec<lsp::SelectionRange>>> {
    let Some(file) = snap.file(&params.text_document.uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let offsets: Vec<_> = params.positions.iter().map(|&p| from_proto::offset(index, p, snap.encoding)).collect();
    let chains = snap.analysis.selection_ranges(file, &offsets)?;
    Ok(Some(
        chains
            .iter()
            .zip(&params.positions)
            .map(|(ranges, &at)| to_proto::selection_range(index, ranges, at, snap.encoding))
            .collect(),
    ))
}

pub fn workspace_symbols(snap: &Snapshot, query: &str) -> Cancellable<Vec<lsp::SymbolInformation>> {
    let mut found = Vec::new();
    for symbol in snap.analysis.workspace_symbols(query, 500)? {
        found.extend(to_proto::workspace_symbol(snap, symbol)?);
    }
    Ok(found)
}

/// The semantic tokens of a document in LSP's relative encoding.
pub fn semantic_token_data(snap: &Snapshot, uri: &lsp::Uri) -> Cancellable<Option<Vec<u32>>> {
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let tokens = snap.analysis.semantic_tokens(file)?;
    let text = snap.analysis.file_text(file);
    Ok(Some(to_proto::semantic_token_data(text, index, &tokens, snap.encoding, &|| snap.analysis.check_cancelled())?))
}

pub fn code_actions(
    snap: &Snapshot,
    params: lsp::CodeActionParams,
) -> Cancellable<Option<Vec<lsp::CodeActionOrCommand>>> {
    let Some((file, range)) = snap.file_range(&params.text_document.uri, params.range)? else {
        return Ok(None);
    };
    let index = snap.analysis.line_index(file)?;
    let fixes = snap.analysis.quick_fixes(file, range)?;
    Ok(Some(fixes.into_iter().map(|fix| to_proto::code_action(snap, index, fix)).collect::<Cancellable<_>>()?))
}

pub fn inlay_hints(snap: &Snapshot, params: lsp::InlayHintParams) -> Cancellable<Option<Vec<lsp::InlayHint>>> {
    let Some((file, range)) = snap.file_range(&params.text_document.uri, params.range)? else {
        return Ok(None);
    };
    let index = snap.analysis.line_index(file)?;
    let hints = snap.analysis.inlay_hints(file, range)?;
    Ok(Some(hints.into_iter().map(|hint| to_proto::inlay_hint(index, hint, snap.encoding)).collect()))
}

pub fn signature_help(snap: &Snapshot, at: lsp::TextDocumentPositionParams) -> Cancellable<Option<lsp::SignatureHelp>> {
    let Some((file, offset)) = snap.file_position(&at.text_document.uri, at.position)? else {
        return Ok(None);
    };
    Ok(snap.analysis.signature_help(file, offset)?.map(to_proto::signature_help))
}
