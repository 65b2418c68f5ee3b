//! Text positions and changes: the line index converts byte offsets to line/column positions
//! (UTF-8 bytes, UTF-16 units or characters) and back, in time logarithmic in the text, whatever
//! the length of a line; `with_edits` makes a batch of edits in a text.
//!
//! Lines end as LSP says they do: at `\n`, at `\r\n` and at a lone `\r`. A position never points
//! into a line terminator: columns past a line's end clamp to the end of its content.

use rowan::{TextRange, TextSize};

/// Where every line of a text starts and ends, and where its non-ASCII characters are.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineIndex {
    /// Offset of the first byte of each line.
    line_starts: Vec<u32>,
    /// Offset just past each line's content (its terminator not included).
    line_ends: Vec<u32>,
    /// Every character longer than one byte, in text order.
    wide_chars: Vec<WideChar>,
    len: u32,
}

/// A character of more than one UTF-8 byte, with how many columns it saved in the other units
/// counting every wide character up to and including it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct WideChar {
    start: u32,
    len_utf8: u8,
    /// Bytes minus UTF-16 units over this and every earlier wide character.
    utf16_savings: u32,
    /// Bytes minus characters over this and every earlier wide character.
    char_savings: u32,
}

impl WideChar {
    fn end(&self) -> u32 {
        self.start + u32::from(self.len_utf8)
    }

    /// Columns this character takes in `unit`.
    fn width(&self, unit: ColumnUnit) -> u32 {
        match unit {
            ColumnUnit::Utf8 => u32::from(self.len_utf8),
            ColumnUnit::Utf16 => 1 + u32::from(self.len_utf8 == 4),
            ColumnUnit::Char => 1,
        }
    }

    fn savings(&self, unit: ColumnUnit) -> u32 {
        match unit {
            ColumnUnit::Utf8 => 0,
            ColumnUnit::Utf16 => self.utf16_savings,
            ColumnUnit::Char => self.char_savings,
        }
    }
}

/// A zero-based line and column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct LineCol {
    pub line: u32,
    /// Column in the unit asked for (bytes, UTF-16 code units or characters).
    pub col: u32,
}

/// The unit a column counts in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnUnit {
    Utf8,
    Utf16,
    Char,
}

impl LineIndex {
    pub fn new(text: &str) -> LineIndex {
        let bytes = text.as_bytes();
        let mut line_starts = vec![0];
        let mut line_ends = Vec::new();
        let mut wide_chars = Vec::new();
        let (mut utf16_savings, mut char_savings) = (0, 0);
        let mut i = 0;
        while i < bytes.len() {
            match bytes[i] {
                b'\n' => {
                    line_ends.push(i as u32);
                    line_starts.push(i as u32 + 1);
                    i += 1;
                }
                b'\r' => {
                    line_ends.push(i as u32);
                    i += if bytes.get(i + 1) == Some(&b'\n') { 2 } else { 1 };
                    line_starts.push(i as u32);
                }
                b if b < 0x80 => i += 1,
                _ => {
                    let ch = text[i..].chars().next().unwrap_or('\u{fffd}');
                    let len_utf8 = ch.len_utf8();
                    utf16_savings += (len_utf8 - ch.len_utf16()) as u32;
                    char_savings += len_utf8 as u32 - 1;
                    wide_chars.push(WideChar {
                        start: i as u32,
                        len_utf8: len_utf8 as u8,
                        utf16_savings,
                        char_savings,
                    });
                    i += len_utf8;
                }
            }
        }
        line_ends.push(bytes.len() as u32);
        LineIndex { line_starts, line_ends, wide_chars, len: bytes.len() as u32 }
    }

    /// The line `offset` is on (an offset inside a `\r\n` belongs to the line it ends).
    fn line_of(&self, offset: u32) -> usize {
        self.line_starts.partition_point(|&start| start <= offset) - 1
    }

    /// Savings in `unit` of the wide characters that end at or before `offset`.
    fn savings_before(&self, offset: u32, unit: ColumnUnit) -> u32 {
        let n = self.wide_chars.partition_point(|w| w.end() <= offset);
        n.checked_sub(1).map_or(0, |last| self.wide_chars[last].savings(unit))
    }

    /// Line and column of `offset` (clamped to the text; inside a character: its start; inside a
    /// line terminator: the line's end).
    pub fn line_col(&self, offset: TextSize, unit: ColumnUnit) -> LineCol {
        let mut offset = u32::from(offset).min(self.len);
        let line = self.line_of(offset);
        offset = offset.min(self.line_ends[line]);
        // Inside a wide character: its start.
        let next = self.wide_chars.partition_point(|w| w.start <= offset);
        if let Some(w) = next.checked_sub(1).map(|i| self.wide_chars[i]) {
            if offset < w.end() {
                offset = w.start;
            }
        }
        let start = self.line_starts[line];
        let col = (offset - start) - (self.savings_before(offset, unit) - self.savings_before(start, unit));
        LineCol { line: line as u32, col }
    }

    /// The byte offset of a line and column (in `unit`), clamped to the end of the line's
    /// content; a column inside a character gives the character's start; `None` for a line
    /// past the end of the text.
    pub fn offset(&self, at: LineCol, unit: ColumnUnit) -> Option<TextSize> {
        let line = at.line as usize;
        let start = *self.line_starts.get(line)?;
        let end = self.line_ends[line];
        let base = self.savings_before(start, unit);
        // The wide characters of this line, and the column each starts at.
        let first = self.wide_chars.partition_point(|w| w.start < start);
        let last = self.wide_chars.partition_point(|w| w.start < end);
        let line_wide = &self.wide_chars[first..last];
        let col_of = |w: &WideChar| (w.start - start) - (self.savings_before(w.start, unit) - base);
        // The last wide character that starts before the column.
        let before = line_wide.partition_point(|w| col_of(w) < at.col);
        let offset = match before.checked_sub(1).map(|i| line_wide[i]) {
            None => u64::from(start) + u64::from(at.col),
            Some(w) => {
                let after = col_of(&w) + w.width(unit);
                if at.col < after {
                    u64::from(w.start)
                } else {
                    u64::from(w.end()) + u64::from(at.col - after)
                }
            }
        };
        Some((offset.min(u64::from(end)) as u32).into())
    }

    /// The content of line `line` (its terminator not included); `None` past the last line.
    pub fn line_range(&self, line: usize) -> Option<TextRange> {
        Some(TextRange::new(self.line_starts.get(line).copied()?.into(), self.line_ends[line].into()))
    }

    /// The pieces of `range` on each line it touches, terminators left out (a piece may be
    /// empty).
    pub fn lines_of(&self, range: TextRange) -> impl Iterator<Item = TextRange> + '_ {
        let (start, end) = (u32::from(range.start()).min(self.len), u32::from(range.end()).min(self.len));
        (self.line_of(start)..=self.line_of(end.max(start))).filter_map(move |line| {
            let piece_start = self.line_starts[line].max(start);
            let piece_end = self.line_ends[line].min(end);
            (piece_start <= piece_end).then(|| TextRange::new(piece_start.into(), piece_end.into()))
        })
    }

    /// The length of the text, the offset just past its end.
    pub fn text_len(&self) -> TextSize {
        self.len.into()
    }

    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }
}

/// How many line breaks `text` holds (`\r\n` counts once, a lone `\r` counts).
pub fn line_breaks(text: &str) -> usize {
    let bytes = text.as_bytes();
    bytes.iter().enumerate().filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n'))).count()
}

/// The line terminator a document uses: that of its first line (`\n` if it has none), as
/// rustfmt's `newline_style = "Auto"` decides.
pub fn line_ending(text: &str) -> &'static str {
    match text.find(['\n', '\r']).map(|i| &text[i..]) {
        Some(rest) if rest.starts_with("\r\n") => "\r\n",
        Some(rest) if rest.starts_with('\r') => "\r",
        _ => "\n",
    }
}

/// `text` with every line break (`\n`, `\r\n`, lone `\r`) written as `ending`.
pub fn with_line_ending(text: &str, ending: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(['\n', '\r']) {
        out.push_str(&rest[..i]);
        out.push_str(ending);
        let skip = if rest[i..].starts_with("\r\n") { 2 } else { 1 };
        rest = &rest[i + skip..];
    }
    out.push_str(rest);
    out
}

/// `text` with `edits` made, each range one of `text` as it is (the last first, so the others
/// stay where they are).
pub fn with_edits<'a>(text: &str, edits: impl IntoIterator<Item = (TextRange, &'a str)>) -> String {
    let mut edits: Vec<(TextRange, &str)> = edits.into_iter().collect();
    edits.sort_by_key(|(range, _)| std::cmp::Reverse(range.start()));
    let mut text = text.to_string();
    for (range, new) in edits {
        text.replace_range(std::ops::Range::<usize>::from(range), new);
    }
    text
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    #[test]
    fn columns_in_each_unit() {
        let index = LineIndex::new("ab\nä😀x\n");
        let at = |o: u32, u| index.line_col(o.into(), u);
        assert_eq!(at(0, ColumnUnit::Utf8), LineCol { line: 0, col: 0 });
        assert_eq!(at(3, ColumnUnit::Utf8), LineCol { line: 1, col: 0 });
        // 'x' after 'ä' (2 bytes) and '😀' (4 bytes, 2 UTF-16 units).
        assert_eq!(at(9, ColumnUnit::Utf8), LineCol { line: 1, col: 6 });
        assert_eq!(at(9, ColumnUnit::Utf16), LineCol { line: 1, col: 3 });
        assert_eq!(at(9, ColumnUnit::Char), LineCol { line: 1, col: 2 });
        // Inside the emoji: its start.
        assert_eq!(at(7, ColumnUnit::Char), LineCol { line: 1, col: 1 });
        assert_eq!(at(100, ColumnUnit::Utf8), LineCol { line: 2, col: 0 });
    }

    #[test]
    fn every_offset_round_trips_in_every_unit() {
        let text = "ab\nä😀x\n// ümlaut €\n";
        let index = LineIndex::new(text);
        for unit in [ColumnUnit::Utf8, ColumnUnit::Utf16, ColumnUnit::Char] {
            for offset in (0..=text.len()).filter(|&o| text.is_char_boundary(o)) {
                let line_col = index.line_col((offset as u32).into(), unit);
                assert_eq!(index.offset(line_col, unit), Some((offset as u32).into()), "{unit:?} {offset}");
            }
        }
        assert_eq!(index.offset(LineCol { line: 9, col: 0 }, ColumnUnit::Utf8), None);
        // A column past the end of a line clamps to the line end.
        assert_eq!(index.offset(LineCol { line: 0, col: 99 }, ColumnUnit::Utf16), Some(2.into()));
        // A UTF-16 column between the halves of a surrogate pair: the character's start.
        assert_eq!(index.offset(LineCol { line: 1, col: 2 }, ColumnUnit::Utf16), Some(5.into()));
    }

    #[test]
    fn crlf_and_lone_cr_end_lines() {
        let text = "a\r\nbc\rd\n\re";
        let index = LineIndex::new(text);
        assert_eq!(index.line_count(), 5);
        let at = |o: u32| index.line_col(o.into(), ColumnUnit::Utf16);
        assert_eq!(at(1), LineCol { line: 0, col: 1 });
        // Between `\r` and `\n`: still the end of line 0, never a column past it.
        assert_eq!(at(2), LineCol { line: 0, col: 1 });
        assert_eq!(at(3), LineCol { line: 1, col: 0 });
        assert_eq!(at(6), LineCol { line: 2, col: 0 });
        assert_eq!(at(8), LineCol { line: 3, col: 0 });
        assert_eq!(at(9), LineCol { line: 4, col: 0 });
        // Columns past a CRLF line's end stop before its `\r`.
        assert_eq!(index.offset(LineCol { line: 0, col: 5 }, ColumnUnit::Utf16), Some(1.into()));
        assert_eq!(index.offset(LineCol { line: 1, col: 5 }, ColumnUnit::Utf16), Some(5.into()));
        assert_eq!(index.line_range(1), Some(TextRange::new(3.into(), 5.into())));
        let pieces: Vec<_> = index.lines_of(TextRange::new(0.into(), 7.into())).collect();
        assert_eq!(
            pieces,
            [
                TextRange::new(0.into(), 1.into()),
                TextRange::new(3.into(), 5.into()),
                TextRange::new(6.into(), 7.into())
            ]
        );
    }

    #[test]
    fn line_endings() {
        assert_eq!(line_breaks("a\r\nb\rc\nd"), 3);
        assert_eq!(line_ending("a\r\nb\n"), "\r\n");
        assert_eq!(line_ending("a\rb\r\n"), "\r");
        assert_eq!(line_ending("ab"), "\n");
        assert_eq!(with_line_ending("a\r\nb\rc\nd\n", "\r\n"), "a\r\nb\r\nc\r\nd\r\n");
        assert_eq!(with_line_ending("a\r\nb\r", "\n"), "a\nb\n");
    }

    /// An LSP client's model of a document: lines split at `\r\n`, `\r` and `\n`, columns
    /// counted in UTF-16 units over each line's content.
    fn client_positions(text: &str) -> Vec<(usize, LineCol)> {
        let mut out = Vec::new();
        let (mut line, mut col) = (0, 0);
        let mut chars = text.char_indices().peekable();
        while let Some((i, ch)) = chars.next() {
            out.push((i, LineCol { line, col }));
            match ch {
                '\r' if chars.peek().is_some_and(|&(_, c)| c == '\n') => {
                    let (j, _) = chars.next().unwrap_or_default();
                    out.push((j, LineCol { line, col }));
                    (line, col) = (line + 1, 0);
                }
                '\r' | '\n' => (line, col) = (line + 1, 0),
                _ => col += ch.len_utf16() as u32,
            }
        }
        out.push((text.len(), LineCol { line, col }));
        out
    }

    proptest! {
        #[test]
        fn agrees_with_a_clients_line_model(text in "[a\\r\\nä😀 ]{0,40}") {
            let index = LineIndex::new(&text);
            for (offset, expected) in client_positions(&text) {
                let got = index.line_col((offset as u32).into(), ColumnUnit::Utf16);
                prop_assert_eq!(got, expected, "offset {}", offset);
                // Back: the offset, except inside a `\r\n`, which maps to the line end.
                let back = usize::from(index.offset(got, ColumnUnit::Utf16).unwrap());
                let inside_crlf = offset > 0 && text.as_bytes().get(offset - 1) == Some(&b'\r') && text.as_bytes().get(offset) == Some(&b'\n');
                prop_assert_eq!(back, if inside_crlf { offset - 1 } else { offset });
            }
        }
    }
}
