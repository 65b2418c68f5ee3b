//! Syntax: lexer, error-tolerant parser and the lossless rowan tree of a GU-DSL document.
//!
//! [`parse`] never fails: it returns a tree that holds every byte of the input (comments and
//! malformed text included) plus the syntax errors found on the way.

mod builder;
mod error;
mod grammar;
mod kind;
pub mod lexer;
mod node_kind;
mod parser;
#[cfg(test)]
mod tests;
mod token_set;
mod unclosed;

pub use error::{SyntaxError, SyntaxErrorCode};
pub use kind::SyntaxKind;
pub use node_kind::NodeKind;
pub use rowan::{TextRange, TextSize};

/// The rowan language tag of GU-DSL trees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum GuDsl {}

impl rowan::Language for GuDsl {
    type Kind = SyntaxKind;

    fn kind_from_raw(raw: rowan::SyntaxKind) -> SyntaxKind {
        SyntaxKind::from_raw(raw.0).unwrap_or(SyntaxKind::ERROR)
    }

    fn kind_to_raw(kind: SyntaxKind) -> rowan::SyntaxKind {
        kind.into()
    }
}

pub type SyntaxNode = rowan::SyntaxNode<GuDsl>;
pub type SyntaxToken = rowan::SyntaxToken<GuDsl>;
pub type SyntaxElement = rowan::SyntaxElement<GuDsl>;

/// The result of parsing one document: a green tree (cheap to clone, shareable across threads)
/// and the syntax errors, ordered by position.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Parse {
    green: rowan::GreenNode,
    errors: Vec<SyntaxError>,
}

impl Parse {
    /// The root node (`SOURCE_FILE`) of the tree.
    pub fn syntax_node(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.green.clone())
    }

    pub fn green(&self) -> &rowan::GreenNode {
        &self.green
    }

    pub fn errors(&self) -> &[SyntaxError] {
        &self.errors
    }
}

/// Parses a whole GU-DSL document.
pub fn parse(text: &str) -> Parse {
    let lexed = lexer::lex(text);
    // The parser's input goes before the tree is built: its memory serves the tree's nodes.
    let (events, mut errors) = grammar::source_file(&parser::Input::new(text, &lexed));
    let green = builder::build_tree(text, &lexed, events);
    if !lexed.errors.is_empty() {
        report_lex_errors(&lexed, &mut errors);
    }
    unclosed::blame_unclosed_brace(text, &lexed, &mut errors);
    errors.sort_by_key(|e| (e.range.start(), e.range.end()));
    Parse { green, errors }
}

/// Adds the lexer's errors to the parser's: a malformed token explains the parser errors right
/// around it, so it is reported alone.
fn report_lex_errors(lexed: &lexer::LexedText, errors: &mut Vec<SyntaxError>) {
    let mut starts = Vec::with_capacity(lexed.tokens.len() + 1);
    let mut offset = 0u32;
    for token in &lexed.tokens {
        starts.push(offset);
        offset += token.len;
    }
    starts.push(offset);
    let mut lex_errors = Vec::with_capacity(lexed.errors.len());
    for lex_error in &lexed.errors {
        let i = lex_error.token;
        let range = TextRange::new(starts[i].into(), starts[i + 1].into());
        let before = (0..i).rev().find(|&j| !lexed.tokens[j].kind.is_trivia()).map_or(0, |j| starts[j + 1]);
        let after =
            (i + 1..lexed.tokens.len()).find(|&j| !lexed.tokens[j].kind.is_trivia()).map_or(offset, |j| starts[j + 1]);
        errors.retain(|e| !(before..=after).contains(&u32::from(e.range.start())));
        lex_errors.push(SyntaxError::new(lex_error.code, lex_error.message.clone(), range));
    }
    errors.extend(lex_errors);
}

/// Indented dump of a tree, one node or token a line, with the errors at the end: the format
/// of the parser's golden files.
pub fn debug_dump(parse: &Parse) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let mut indent = 0usize;
    for event in parse.syntax_node().preorder_with_tokens() {
        match event {
            rowan::WalkEvent::Enter(element) => {
                let range = element.text_range();
                let _ = write!(out, "{:indent$}{:?}@{:?}", "", element.kind(), range, indent = indent);
                if let rowan::NodeOrToken::Token(token) = &element {
                    let _ = write!(out, " {:?}", token.text());
                }
                out.push('\n');
                if element.as_node().is_some() {
                    indent += 2;
                }
            }
            rowan::WalkEvent::Leave(element) => {
                if element.as_node().is_some() {
                    indent -= 2;
                }
            }
        }
    }
    for error in parse.errors() {
        let _ = writeln!(out, "error {:?}: {}: {}", error.range, error.code.as_str(), error.message);
    }
    out
}
