//! Syntax errors: a stable code, a byte range and a message a user can act on.

use rowan::TextRange;

/// Stable codes of syntax errors. Semantic diagnostics use `E02xx` and up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SyntaxErrorCode {
    /// A token the grammar does not allow here, or a missing one.
    UnexpectedToken,
    /// A construct is missing its closing delimiter.
    UnclosedDelimiter,
    /// A string or character literal without its closing quote.
    UnterminatedLiteral,
    /// A block comment without `*/`.
    UnterminatedComment,
    /// A character that starts no token.
    UnknownCharacter,
    /// Nesting deeper than the parser follows; the nested text is kept but not analysed.
    NestingTooDeep,
}

impl SyntaxErrorCode {
    /// The code as printed: `E0001`…
    pub fn as_str(self) -> &'static str {
        match self {
            SyntaxErrorCode::UnexpectedToken => "E0001",
            SyntaxErrorCode::UnclosedDelimiter => "E0002",
            SyntaxErrorCode::UnterminatedLiteral => "E0003",
            SyntaxErrorCode::UnterminatedComment => "E0004",
            SyntaxErrorCode::UnknownCharacter => "E0005",
            SyntaxErrorCode::NestingTooDeep => "E0006",
        }
    }

    /// What the code means, in a few words (for rule lists such as SARIF's).
    pub fn summary(self) -> &'static str {
        match self {
            SyntaxErrorCode::UnexpectedToken => "a token the grammar does not allow here, or a missing one",
            SyntaxErrorCode::UnclosedDelimiter => "a construct without its closing delimiter",
            SyntaxErrorCode::UnterminatedLiteral => "a string or character literal without its closing quote",
            SyntaxErrorCode::UnterminatedComment => "a block comment without `*/`",
            SyntaxErrorCode::UnknownCharacter => "a character that starts no token",
            SyntaxErrorCode::NestingTooDeep => "nesting deeper than the parser follows",
        }
    }
}

/// One syntax error.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SyntaxError {
    pub code: SyntaxErrorCode,
    pub message: String,
    pub range: TextRange,
}

impl SyntaxError {
    pub fn new(code: SyntaxErrorCode, message: impl Into<String>, range: TextRange) -> Self {
        SyntaxError { code, message: message.into(), range }
    }
}
