//! Line index: converts byte offsets to line/column positions (UTF-8 bytes or UTF-16 units).

use crate::syntax::TextSize;

/// Start offsets of every line of a text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineIndex {
    line_starts: Vec<u32>,
    text: std::sync::Arc<str>,
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
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i as u32 + 1));
        LineIndex { line_starts, text: text.into() }
    }

    /// Line and column of `offset` (clamped to the text; inside a character: its start).
    pub fn line_col(&self, offset: TextSize, unit: ColumnUnit) -> LineCol {
        let mut offset = u32::from(offset).min(self.text.len() as u32) as usize;
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&start| start as usize <= offset) - 1;
        let line_text = &self.text[self.line_starts[line] as usize..offset];
        let col = match unit {
            ColumnUnit::Utf8 => line_text.len(),
            ColumnUnit::Utf16 => line_text.encode_utf16().count(),
            ColumnUnit::Char => line_text.chars().count(),
        };
        LineCol { line: line as u32, col: col as u32 }
    }

    /// The byte offset of a line and column (in `unit`), clamped to the line's end; `None` for a
    /// line past the end of the text.
    pub fn offset(&self, at: LineCol, unit: ColumnUnit) -> Option<TextSize> {
        let start = *self.line_starts.get(at.line as usize)? as usize;
        let end = self.line_starts.get(at.line as usize + 1).map_or(self.text.len(), |&e| e as usize);
        let line = &self.text[start..end];
        let mut col = 0u32;
        for (i, ch) in line.char_indices() {
            if col >= at.col || ch == '\n' {
                return Some(((start + i) as u32).into());
            }
            col += match unit {
                ColumnUnit::Utf8 => ch.len_utf8() as u32,
                ColumnUnit::Utf16 => ch.len_utf16() as u32,
                ColumnUnit::Char => 1,
            };
        }
        Some((end as u32).into())
    }

    /// The length of the text, the offset just past its end.
    pub fn text_len(&self) -> TextSize {
        TextSize::of(&*self.text)
    }

    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }
}

#[cfg(test)]
mod tests {
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
    }
}
