//! Folding ranges: every braced construct spanning lines, comment blocks and import groups.

use crate::{
    syntax::{SyntaxKind, SyntaxNode, TextRange},
    text::{ColumnUnit, LineIndex},
};

/// What a fold hides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoldKind {
    Region,
    Comment,
    Imports,
}

/// A foldable range.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fold {
    pub range: TextRange,
    pub kind: FoldKind,
}

/// The folding ranges of a tree: braces that open and close on different lines, runs of
/// comment lines, and runs of imports.
pub fn folding_ranges(root: &SyntaxNode, index: &LineIndex) -> Vec<Fold> {
    let line = |offset| index.line_col(offset, ColumnUnit::Utf8).line;
    let mut folds = Vec::new();
    let mut open: Vec<rowan::TextSize> = Vec::new();
    let mut comment_run: Option<TextRange> = None;
    for token in root.descendants_with_tokens().filter_map(|e| e.into_token()) {
        match token.kind() {
            SyntaxKind::L_CURLY => open.push(token.text_range().start()),
            SyntaxKind::R_CURLY => {
                if let Some(start) = open.pop() {
                    let end = token.text_range().end();
                    if line(start) != line(end) {
                        folds.push(Fold { range: TextRange::new(start, end), kind: FoldKind::Region });
                    }
                }
            }
            SyntaxKind::LINE_COMMENT | SyntaxKind::BLOCK_COMMENT => {
                let range = token.text_range();
                comment_run = Some(match comment_run {
                    Some(run) if line(run.end()) + 1 >= line(range.start()) => run.cover(range),
                    Some(run) => {
                        push_multiline(&mut folds, run, FoldKind::Comment, &line);
                        range
                    }
                    None => range,
                });
            }
            SyntaxKind::WHITESPACE => {}
            _ => {
                if let Some(run) = comment_run.take() {
                    push_multiline(&mut folds, run, FoldKind::Comment, &line);
                }
            }
        }
    }
    if let Some(run) = comment_run {
        push_multiline(&mut folds, run, FoldKind::Comment, &line);
    }
    // Consecutive imports of one scope.
    for parent in root.descendants() {
        let mut run: Option<TextRange> = None;
        for child in parent.children() {
            if child.kind() == SyntaxKind::IMPORT {
                run = Some(run.map_or(child.text_range(), |r| r.cover(child.text_range())));
            } else if let Some(r) = run.take() {
                push_multiline(&mut folds, r, FoldKind::Imports, &line);
            }
        }
        if let Some(r) = run {
            push_multiline(&mut folds, r, FoldKind::Imports, &line);
        }
    }
    folds.sort_by_key(|f| (f.range.start(), f.range.end()));
    folds
}

fn push_multiline(folds: &mut Vec<Fold>, range: TextRange, kind: FoldKind, line: &dyn Fn(rowan::TextSize) -> u32) {
    if line(range.start()) != line(range.end()) {
        folds.push(Fold { range, kind });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braces_comments_and_imports_fold() {
        let text = "// one\n// two\nClassDiagram D\n{\n    import A.*;\n    import B.*;\n    class C { }\n    class E\n    {\n    }\n}\n";
        let parse = crate::parse(text);
        let folds = folding_ranges(&parse.syntax_node(), &LineIndex::new(text));
        let described: Vec<(FoldKind, &str)> = folds.iter().map(|f| (f.kind, &text[f.range])).collect();
        assert_eq!(
            described,
            vec![
                (FoldKind::Comment, "// one\n// two"),
                (FoldKind::Region, &text[text.find("{\n    import").unwrap()..text.len() - 1]),
                (FoldKind::Imports, "import A.*;\n    import B.*;"),
                (FoldKind::Region, "{\n    }"),
            ]
        );
    }
}
