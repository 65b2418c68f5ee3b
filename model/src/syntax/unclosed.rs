//! Which `{` a missing `}` belongs to. The parser notices a missing `}` where the text runs
//! out of closing braces — often at the end of an enclosing method or class — but the brace
//! left open is usually an inner one (`if (n > 0) {` without its `}`): its `}` went to it, and
//! the `}` it took lines up with an outer block's line, not with its own. As rustc does, the
//! indentation says which: the first `{` whose matching `}` starts a line indented unlike
//! the `{`'s line is reported instead, at that `{`.

use rowan::{TextRange, TextSize};

use super::{error::SyntaxErrorCode, lexer::LexedText, SyntaxError, SyntaxKind};

/// Rewrites the first "expected `}`" error of `errors` to point at the `{` the indentation
/// says is unclosed, if one lies before it.
pub(super) fn blame_unclosed_brace(text: &str, lexed: &LexedText, errors: &mut Vec<SyntaxError>) {
    let missing = errors
        .iter()
        .enumerate()
        .filter(|(_, e)| e.code == SyntaxErrorCode::UnclosedDelimiter && e.message.starts_with("expected `}`"))
        .min_by_key(|(_, e)| e.range.start())
        .map(|(i, _)| i);
    let Some(index) = missing else { return };
    let error = &mut errors[index];
    let Some((open, close)) = misindented_pair(text, lexed).filter(|(open, _)| *open < error.range.start()) else {
        return;
    };
    let (open_line, open_start) = line_of(text, open);
    let (close_line, _) = line_of(text, close);
    let opener = opened_by(text, open_start, open);
    error.range = TextRange::at(open, TextSize::from(1));
    error.message = format!(
        "the `{{` of `{opener}` (line {}) has no `}}` of its own: the `}}` on line {} closes it, but is indented as \
         an outer block's; add this block's `}}`",
        open_line + 1,
        close_line + 1
    );
    // A transition read inside the block belongs to the node the block should have ended in.
    errors.retain(|e| !(e.message.ends_with("found `=>`") && open < e.range.start() && e.range.start() < close));
}

/// The first `}` (in the text's order) that begins a line indented other than the line of
/// the `{` it matches, and that `{`: their offsets. Blocks close inside out, so the first such
/// `}` closes the innermost block whose own `}` is missing.
fn misindented_pair(text: &str, lexed: &LexedText) -> Option<(TextSize, TextSize)> {
    let mut open: Vec<TextSize> = Vec::new();
    let mut offset = TextSize::from(0);
    for token in &lexed.tokens {
        match token.kind {
            SyntaxKind::L_CURLY => open.push(offset),
            SyntaxKind::R_CURLY => {
                if let Some(start) = open.pop() {
                    let close_indent = starts_line(text, offset).then(|| indentation(text, offset));
                    if close_indent.is_some_and(|indent| indent != indentation(text, start)) {
                        return Some((start, offset));
                    }
                }
            }
            _ => {}
        }
        offset += TextSize::from(token.len);
    }
    None
}

/// What a `{` at `open` (on the line starting at `line_start`) opens, as written: its line up
/// to the brace, or the line before for a brace on a line of its own (`public class Image` ⏎ `{`).
fn opened_by(text: &str, line_start: usize, open: TextSize) -> String {
    let before = text[line_start..usize::from(open)].trim();
    if !before.is_empty() {
        return format!("{before} {{");
    }
    let previous = text[..line_start].lines().rev().map(str::trim).find(|l| !l.is_empty());
    previous.map_or_else(|| "{".to_string(), str::to_string)
}

/// The line number (from 0) of `at` and the offset its line starts at.
fn line_of(text: &str, at: TextSize) -> (usize, usize) {
    let before = &text[..usize::from(at)];
    (before.matches('\n').count(), before.rfind('\n').map_or(0, |i| i + 1))
}

/// The leading whitespace of the line `at` is on.
fn indentation(text: &str, at: TextSize) -> &str {
    let (_, start) = line_of(text, at);
    let line = &text[start..];
    &line[..line.len() - line.trim_start_matches([' ', '\t']).len()]
}

/// Whether only whitespace precedes `at` on its line.
fn starts_line(text: &str, at: TextSize) -> bool {
    let (_, start) = line_of(text, at);
    text[start..usize::from(at)].chars().all(|c| c == ' ' || c == '\t')
}

#[cfg(test)]
mod tests {
    use crate::syntax::parse;

    fn errors(text: &str) -> Vec<(u32, String)> {
        parse(text).errors().iter().map(|e| (u32::from(e.range.start()), e.message.clone())).collect()
    }

    #[test]
    fn an_inner_block_left_open_is_blamed_not_the_method() {
        let text = "ClassDiagram A\n{\n    public class H\n    {\n        public int run(int n)\n        {\n            if (n > 0) {\n                n = n - 1;\n            return n;\n        }\n        public int other() { return 1; }\n    }\n}\n";
        let found = errors(text);
        let at = text.find("{\n                n").unwrap() as u32;
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0, at, "{found:?}");
        assert!(found[0].1.contains("`if (n > 0) {` (line 7)"), "{found:?}");
    }

    #[test]
    fn a_missing_brace_at_the_end_of_well_indented_text_stays_where_it_is() {
        let text = "ClassDiagram A\n{\n    public class H { }\n";
        let found = errors(text);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0 as usize, text.trim_end().len(), "{found:?}");
        assert!(found[0].1.starts_with("expected `}` to close class diagram"), "{found:?}");
    }
}
