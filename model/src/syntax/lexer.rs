//! Lexer: splits GU-DSL text into tokens that cover every byte, with errors for malformed ones.

use super::{SyntaxErrorCode, SyntaxKind, SyntaxKind::*};

/// One lexed token: its kind and its length in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    pub kind: SyntaxKind,
    pub len: u32,
}

/// A malformed token (unterminated string or comment, stray character).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    pub code: SyntaxErrorCode,
    pub message: String,
    /// Index into the token list.
    pub token: usize,
}

/// Tokens of a text, in order; their lengths add up to the text length.
#[derive(Debug, Default)]
pub struct LexedText {
    pub tokens: Vec<Token>,
    pub errors: Vec<LexError>,
}

/// Lexes `text` completely. Never fails: bad input becomes `UNKNOWN` tokens plus errors.
pub fn lex(text: &str) -> LexedText {
    let mut lexer = Lexer { bytes: text.as_bytes(), text, pos: 0, out: LexedText::default() };
    // Room for a token a byte, the most there can be: the buffer is never copied as it grows,
    // and the room left unused (about half) is never touched.
    lexer.out.tokens.reserve(text.len() + 1);
    while lexer.pos < lexer.bytes.len() {
        lexer.next_token();
    }
    lexer.out
}

struct Lexer<'a> {
    bytes: &'a [u8],
    text: &'a str,
    pos: usize,
    out: LexedText,
}

impl Lexer<'_> {
    fn peek(&self, ahead: usize) -> u8 {
        self.bytes.get(self.pos + ahead).copied().unwrap_or(0)
    }

    fn push(&mut self, kind: SyntaxKind, start: usize) {
        self.out.tokens.push(Token { kind, len: (self.pos - start) as u32 });
    }

    fn error(&mut self, code: SyntaxErrorCode, message: impl Into<String>) {
        let token = self.out.tokens.len() - 1;
        self.out.errors.push(LexError { code, message: message.into(), token });
    }

    fn next_token(&mut self) {
        let start = self.pos;
        let c = self.peek(0);
        match c {
            // A byte-order mark opening the text is trivia, as editors treat it.
            0xEF if start == 0 && self.text.starts_with('\u{feff}') => {
                self.pos += '\u{feff}'.len_utf8();
                self.push(WHITESPACE, start);
            }
            b' ' | b'\t' | b'\n' | b'\r' | b'\x0c' => {
                while matches!(self.peek(0), b' ' | b'\t' | b'\n' | b'\r' | b'\x0c') {
                    self.pos += 1;
                }
                self.push(WHITESPACE, start);
            }
            b'/' if self.peek(1) == b'/' => {
                // To the line end, which may be `\r\n` or a lone `\r`: never including it.
                while self.pos < self.bytes.len() && !matches!(self.bytes[self.pos], b'\n' | b'\r') {
                    self.pos += 1;
                }
                self.push(LINE_COMMENT, start);
            }
            b'/' if self.peek(1) == b'*' => self.block_comment(start),
            b'"' => self.quoted(start, b'"', STRING),
            b'\'' => self.quoted(start, b'\'', CHAR),
            b'0'..=b'9' => self.number(start),
            b'.' if self.peek(1).is_ascii_digit() => self.number(start),
            c if c == b'_' || c.is_ascii_alphabetic() => {
                while matches!(self.peek(0), b'_' | b'a'..=b'z' | b'A'..=b'Z' | b'0'..=b'9') {
                    self.pos += 1;
                }
                let kind = SyntaxKind::from_keyword(&self.text[start..self.pos]).unwrap_or(IDENT);
                self.push(kind, start);
            }
            _ => {
                if let Some((kind, len)) = punctuation(&self.bytes[self.pos..]) {
                    self.pos += len;
                    self.push(kind, start);
                } else {
                    // One whole character, never half of a UTF-8 sequence.
                    let ch = self.text[self.pos..].chars().next().unwrap_or('\u{fffd}');
                    self.pos += ch.len_utf8().max(1);
                    self.push(UNKNOWN, start);
                    self.error(
                        SyntaxErrorCode::UnknownCharacter,
                        format!("unexpected character `{}`", ch.escape_debug()),
                    );
                }
            }
        }
    }

    fn block_comment(&mut self, start: usize) {
        self.pos += 2;
        while self.pos < self.bytes.len() {
            if self.bytes[self.pos] == b'*' && self.peek(1) == b'/' {
                self.pos += 2;
                self.push(BLOCK_COMMENT, start);
                return;
            }
            self.pos += 1;
        }
        self.push(BLOCK_COMMENT, start);
        self.error(SyntaxErrorCode::UnterminatedComment, "unterminated block comment: add `*/`");
    }

    /// A string or character literal. It ends at the closing quote or, unterminated, at the
    /// end of the line, so one missing quote does not swallow the rest of the file.
    fn quoted(&mut self, start: usize, quote: u8, kind: SyntaxKind) {
        self.pos += 1;
        while self.pos < self.bytes.len() {
            match self.bytes[self.pos] {
                b'\\' => self.pos = (self.pos + 2).min(self.bytes.len()),
                b'\n' | b'\r' => break,
                c if c == quote => {
                    self.pos += 1;
                    self.push(kind, start);
                    return;
                }
                _ => self.pos += 1,
            }
        }
        // A backslash before a multi-byte character may have stepped inside it.
        while !self.text.is_char_boundary(self.pos) {
            self.pos += 1;
        }
        self.push(kind, start);
        let what = if kind == STRING { "string literal: add `\"`" } else { "character literal: add `'`" };
        self.error(SyntaxErrorCode::UnterminatedLiteral, format!("unterminated {what}"));
    }

    fn number(&mut self, start: usize) {
        let mut kind = INT_NUMBER;
        if self.peek(0) == b'0' && matches!(self.peek(1), b'x' | b'X') && self.peek(2).is_ascii_hexdigit() {
            self.pos += 2;
            while self.peek(0).is_ascii_hexdigit() {
                self.pos += 1;
            }
        } else {
            self.digits();
            if self.peek(0) == b'.' && self.peek(1).is_ascii_digit() {
                kind = FLOAT_NUMBER;
                self.pos += 1;
                self.digits();
            }
            let exp_digits = match self.peek(1) {
                b'+' | b'-' => self.peek(2).is_ascii_digit(),
                d => d.is_ascii_digit(),
            };
            if matches!(self.peek(0), b'e' | b'E') && exp_digits {
                kind = FLOAT_NUMBER;
                self.pos += 2;
                self.digits();
            }
            if matches!(self.peek(0), b'f' | b'F' | b'd' | b'D') && !is_ident_continue(self.peek(1)) {
                kind = FLOAT_NUMBER;
                self.pos += 1;
            }
        }
        // Integer suffixes (`10u`, `5L`) as in C.
        while kind == INT_NUMBER && matches!(self.peek(0), b'u' | b'U' | b'l' | b'L') {
            self.pos += 1;
        }
        self.push(kind, start);
    }

    fn digits(&mut self) {
        while self.peek(0).is_ascii_digit() {
            self.pos += 1;
        }
    }
}

fn is_ident_continue(c: u8) -> bool {
    c == b'_' || c.is_ascii_alphanumeric()
}

/// Longest punctuation token at the start of `rest`. `>` is always lexed alone: the parser
/// joins `>>`, `>=` and `>>=` so that `A<B<C>>` closes two type-argument lists.
fn punctuation(rest: &[u8]) -> Option<(SyntaxKind, usize)> {
    let at = |i: usize| rest.get(i).copied().unwrap_or(0);
    let three = match (at(0), at(1), at(2)) {
        (b'=', b'=', b'>') => Some(LONG_FAT_ARROW),
        (b'<', b'<', b'=') => Some(SHLEQ),
        _ => None,
    };
    if let Some(kind) = three {
        return Some((kind, 3));
    }
    let two = match (at(0), at(1)) {
        (b'.', b'.') => Some(DOT2),
        (b':', b':') => Some(COLON2),
        (b'=', b'=') => Some(EQ2),
        (b'=', b'>') => Some(FAT_ARROW),
        (b'!', b'=') => Some(NEQ),
        (b'<', b'=') => Some(LTEQ),
        (b'<', b'<') => Some(SHL),
        (b'&', b'&') => Some(AMP2),
        (b'|', b'|') => Some(PIPE2),
        (b'+', b'+') => Some(PLUS2),
        (b'-', b'-') => Some(MINUS2),
        (b'+', b'=') => Some(PLUSEQ),
        (b'-', b'=') => Some(MINUSEQ),
        (b'*', b'=') => Some(STAREQ),
        (b'/', b'=') => Some(SLASHEQ),
        (b'%', b'=') => Some(PERCENTEQ),
        (b'&', b'=') => Some(AMPEQ),
        (b'|', b'=') => Some(PIPEEQ),
        (b'^', b'=') => Some(CARETEQ),
        _ => None,
    };
    if let Some(kind) = two {
        return Some((kind, 2));
    }
    let one = match at(0) {
        b';' => SEMICOLON,
        b',' => COMMA,
        b'.' => DOT,
        b':' => COLON,
        b'(' => L_PAREN,
        b')' => R_PAREN,
        b'{' => L_CURLY,
        b'}' => R_CURLY,
        b'[' => L_BRACK,
        b']' => R_BRACK,
        b'<' => L_ANGLE,
        b'>' => R_ANGLE,
        b'=' => EQ,
        b'!' => BANG,
        b'+' => PLUS,
        b'-' => MINUS,
        b'*' => STAR,
        b'/' => SLASH,
        b'%' => PERCENT,
        b'&' => AMP,
        b'|' => PIPE,
        b'^' => CARET,
        b'~' => TILDE,
        b'?' => QUESTION,
        _ => return None,
    };
    Some((one, 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(SyntaxKind, &str)> {
        let lexed = lex(text);
        let mut pos = 0;
        lexed
            .tokens
            .iter()
            .filter(|t| t.kind != WHITESPACE)
            .map(|t| t.kind)
            .zip(lexed.tokens.iter().filter_map(|t| {
                let s = &text[pos..pos + t.len as usize];
                pos += t.len as usize;
                (t.kind != WHITESPACE).then_some(s)
            }))
            .collect()
    }

    #[test]
    fn numbers_and_ranges() {
        assert_eq!(
            kinds("0..* 1.0f 13.0 2e-3 0xFF 5u .5"),
            vec![
                (INT_NUMBER, "0"),
                (DOT2, ".."),
                (STAR, "*"),
                (FLOAT_NUMBER, "1.0f"),
                (FLOAT_NUMBER, "13.0"),
                (FLOAT_NUMBER, "2e-3"),
                (INT_NUMBER, "0xFF"),
                (INT_NUMBER, "5u"),
                (FLOAT_NUMBER, ".5"),
            ]
        );
    }

    #[test]
    fn arrows_and_angles() {
        assert_eq!(
            kinds("=> ==> >>= <<= A<B<C>>"),
            vec![
                (FAT_ARROW, "=>"),
                (LONG_FAT_ARROW, "==>"),
                (R_ANGLE, ">"),
                (R_ANGLE, ">"),
                (EQ, "="),
                (SHLEQ, "<<="),
                (IDENT, "A"),
                (L_ANGLE, "<"),
                (IDENT, "B"),
                (L_ANGLE, "<"),
                (IDENT, "C"),
                (R_ANGLE, ">"),
                (R_ANGLE, ">"),
            ]
        );
    }

    #[test]
    fn unterminated_string_stops_at_line_end() {
        let lexed = lex("\"abc\nnext");
        assert_eq!(lexed.tokens[0], Token { kind: STRING, len: 4 });
        assert_eq!(lexed.errors.len(), 1);
        assert_eq!(lexed.errors[0].code, SyntaxErrorCode::UnterminatedLiteral);
    }

    #[test]
    fn comments_and_literals_end_before_any_line_terminator() {
        for eol in ["\n", "\r\n", "\r"] {
            let lexed = lex(&format!("// note{eol}\"abc{eol}'x{eol}x"));
            let lens: Vec<_> = lexed.tokens.iter().map(|t| (t.kind, t.len)).collect();
            let eol_len = eol.len() as u32;
            assert_eq!(
                lens,
                [
                    (LINE_COMMENT, 7),
                    (WHITESPACE, eol_len),
                    (STRING, 4),
                    (WHITESPACE, eol_len),
                    (CHAR, 2),
                    (WHITESPACE, eol_len),
                    (IDENT, 1)
                ],
                "{eol:?}"
            );
        }
    }

    #[test]
    fn a_leading_byte_order_mark_is_trivia() {
        let lexed = lex("\u{feff}class");
        assert_eq!(lexed.tokens, [Token { kind: WHITESPACE, len: 3 }, Token { kind: CLASS_KW, len: 5 }]);
        assert!(lexed.errors.is_empty());
        // Elsewhere it is a stray character.
        assert_eq!(lex("a\u{feff}").errors.len(), 1);
        assert!(crate::parse("\u{feff}ClassDiagram D { }").errors().is_empty());
    }

    #[test]
    fn non_ascii_is_one_unknown_token_per_char() {
        let lexed = lex("a€😀");
        assert_eq!(lexed.tokens.iter().map(|t| t.len).collect::<Vec<_>>(), vec![1, 3, 4]);
        assert_eq!(lexed.errors.len(), 2);
    }

    #[test]
    fn keywords_and_contextual_words() {
        assert_eq!(kinds("class swimlane"), vec![(CLASS_KW, "class"), (IDENT, "swimlane")]);
    }
}
