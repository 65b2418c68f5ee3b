//! Conversions at the LSP boundary: byte offsets ↔ positions in the negotiated encoding,
//! model types → LSP types. The model speaks byte offsets only.

use gudsl_model::{
    syntax::{TextRange, TextSize},
    text::{ColumnUnit, LineCol, LineIndex},
};
use tower_lsp_server::ls_types as lsp;

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

    pub fn position(self, index: &LineIndex, offset: TextSize) -> lsp::Position {
        let at = index.line_col(offset, self.0);
        lsp::Position::new(at.line, at.col)
    }

    pub fn range(self, index: &LineIndex, range: TextRange) -> lsp::Range {
        lsp::Range::new(self.position(index, range.start()), self.position(index, range.end()))
    }

    /// The byte offset of a position; positions past the end clamp to the end of the text.
    pub fn offset(self, index: &LineIndex, text_len: usize, position: lsp::Position) -> TextSize {
        index
            .offset(LineCol { line: position.line, col: position.character }, self.0)
            .unwrap_or(TextSize::from(text_len as u32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_and_utf8_positions_round_trip_outside_the_bmp() {
        let text = "// 😀 ä\nClassDiagram X { }\n";
        let index = LineIndex::new(text);
        let x = TextSize::from(text.find('X').unwrap() as u32);
        for encoding in [Encoding(ColumnUnit::Utf8), Encoding(ColumnUnit::Utf16)] {
            let position = encoding.position(&index, x);
            assert_eq!(encoding.offset(&index, text.len(), position), x);
        }
        let after_emoji = TextSize::from(text.find(" ä").unwrap() as u32);
        assert_eq!(Encoding(ColumnUnit::Utf16).position(&index, after_emoji), lsp::Position::new(0, 5));
        assert_eq!(Encoding(ColumnUnit::Utf8).position(&index, after_emoji), lsp::Position::new(0, 7));
    }
}
