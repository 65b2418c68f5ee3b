//! Literals: the token and the value it denotes, as C reads it.

use super::Literal;
use crate::syntax::{SyntaxKind::*, SyntaxToken};

impl Literal {
    pub fn token(&self) -> Option<SyntaxToken> {
        self.syntax.first_token()
    }

    /// What the literal denotes, as C reads it: an integer (decimal or `0x` hex; unsigned with a
    /// `u` suffix or when it does not fit `int`), a floating-point number (`f`/`d` suffixes), a
    /// character's code, a string without its quotes and escapes, `true`, `false`, `null`.
    /// `None` for an integer wider than 64 bits.
    pub fn value(&self) -> Option<LiteralValue> {
        let token = self.token()?;
        let text = token.text();
        Some(match token.kind() {
            INT_NUMBER => {
                let digits = text.trim_end_matches(['l', 'L', 'u', 'U']);
                let value = match digits.strip_prefix("0x").or_else(|| digits.strip_prefix("0X")) {
                    Some(hex) => u64::from_str_radix(hex, 16).ok()?,
                    None => digits.parse::<u64>().ok()?,
                };
                LiteralValue::Int { value, unsigned: text.ends_with(['u', 'U']) || value > i32::MAX as u64 }
            }
            FLOAT_NUMBER => LiteralValue::Float(text.trim_end_matches(['f', 'F', 'd', 'D']).parse().ok()?),
            CHAR => {
                let inner = text.trim_matches('\'');
                LiteralValue::Char(match inner.strip_prefix('\\') {
                    Some(escaped) => unescape(escaped.chars().next()?),
                    None => inner.chars().next()? as u32,
                })
            }
            STRING => {
                let inner = text.strip_prefix('"').unwrap_or(text);
                let inner = inner.strip_suffix('"').unwrap_or(inner);
                let mut out = String::new();
                let mut chars = inner.chars();
                while let Some(c) = chars.next() {
                    match c {
                        '\\' => out.extend(chars.next().and_then(|e| char::from_u32(unescape(e)))),
                        c => out.push(c),
                    }
                }
                LiteralValue::Str(out)
            }
            TRUE_KW => LiteralValue::Bool(true),
            FALSE_KW => LiteralValue::Bool(false),
            _ => LiteralValue::Null,
        })
    }
}

/// The value of a [`Literal`].
#[derive(Debug, Clone, PartialEq)]
pub enum LiteralValue {
    Int {
        value: u64,
        unsigned: bool,
    },
    Float(f64),
    /// A character's code (`'a'`, `'\n'`).
    Char(u32),
    Str(String),
    Bool(bool),
    Null,
}

/// The character C's escape `\c` stands for.
fn unescape(c: char) -> u32 {
    match c {
        'n' => 10,
        't' => 9,
        'r' => 13,
        '0' => 0,
        other => other as u32,
    }
}
