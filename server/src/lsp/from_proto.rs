//! LSP → model: positions to byte offsets in the negotiated encoding, editor changes to
//! line/column edits, and `file:` URIs to paths. Nothing else in the server reads an LSP
//! position.

use gudsl_model::{
    syntax::{TextRange, TextSize},
    text::{LineCol, LineIndex},
    LineColEdit,
};
use tower_lsp_server::ls_types as lsp;

use super::capabilities::Encoding;

/// The path of a `file:` URI, normalized (`..` and `.` taken lexically, so `a/..%2F..%2Fb`
/// is `b`, where a user reading it would look); `None` for any other scheme (`untitled:`, a
/// library document), whose path is no place on disk. The one place a URI becomes a path.
pub fn file_path(uri: &lsp::Uri) -> Option<std::path::PathBuf> {
    let path = uri.scheme().as_str().eq_ignore_ascii_case("file").then(|| uri.to_file_path())??;
    Some(path.into_owned()).filter(|p| p.is_absolute()).map(|p| gudsl_files::lexical(&p))
}

fn line_col(position: lsp::Position) -> LineCol {
    LineCol { line: position.line, col: position.character }
}

/// The byte offset of a position; positions past a line's end clamp to it, past the text's end
/// to the end.
pub fn offset(index: &LineIndex, position: lsp::Position, encoding: Encoding) -> TextSize {
    index.offset(line_col(position), encoding.0).unwrap_or_else(|| index.text_len())
}

/// A request's range as sent, or why it is refused (one that ends before it starts: the
/// spec leaves it undefined, so it is not guessed at).
pub fn ordered_range(range: lsp::Range) -> Result<lsp::Range, String> {
    let (start, end) = (line_col(range.start), line_col(range.end));
    if end < start {
        return Err(format!(
            "the range ends (line {}, character {}) before it starts (line {}, character {})",
            end.line, end.col, start.line, start.col
        ));
    }
    Ok(range)
}

/// A range of byte offsets (of a range checked by [`ordered_range`]; never panics on others).
pub fn text_range(index: &LineIndex, range: lsp::Range, encoding: Encoding) -> TextRange {
    let (start, end) = (offset(index, range.start, encoding), offset(index, range.end, encoding));
    TextRange::new(start.min(end), end.max(start))
}

/// An editor's content changes as edits of the model (each against the text changed so far).
pub fn edits(changes: Vec<lsp::TextDocumentContentChangeEvent>) -> Vec<LineColEdit> {
    changes
        .into_iter()
        .map(|change| LineColEdit {
            range: change.range.map(|r| (line_col(r.start), line_col(r.end))),
            text: change.text,
        })
        .collect()
}
