//! The parser's machinery: token input, markers and the flat event list the grammar emits.
//!
//! As in rust-analyzer, the grammar never builds a tree itself. It emits `Start`/`Token`/`Finish`
//! events; a [`Marker`] must be completed or abandoned (dropping one is a bug caught in debug
//! builds), and [`CompletedMarker::precede`] wraps an already parsed node, for left recursion.

use super::{
    lexer::LexedText, token_set::TokenSet, SyntaxError, SyntaxErrorCode, SyntaxKind, SyntaxKind::*, TextRange,
};

/// Non-trivia tokens with their positions, as the grammar sees them.
pub(crate) struct Input<'t> {
    text: &'t str,
    kinds: Vec<SyntaxKind>,
    /// Contextual keyword an `IDENT` could be remapped to.
    contextual: Vec<Option<SyntaxKind>>,
    /// Byte range of each token.
    ranges: Vec<TextRange>,
    /// Token `i` is immediately followed by token `i + 1` (no trivia between).
    joint: Vec<bool>,
    text_len: u32,
    /// Every `{` of the text has its `}`.
    braces_balanced: bool,
}

impl<'t> Input<'t> {
    pub(crate) fn new(text: &'t str, lexed: &LexedText) -> Input<'t> {
        // Room for every token at once: a buffer that grows is copied and touched twice, and
        // the room trivia leaves unused is never touched.
        let n = lexed.tokens.len();
        let mut input = Input {
            text,
            kinds: Vec::with_capacity(n),
            contextual: Vec::with_capacity(n),
            ranges: Vec::with_capacity(n),
            joint: Vec::with_capacity(n),
            text_len: text.len() as u32,
            braces_balanced: false,
        };
        let mut offset = 0u32;
        let mut previous_was_token = false;
        for token in &lexed.tokens {
            let range = TextRange::at(offset.into(), token.len.into());
            offset += token.len;
            if token.kind.is_trivia() {
                previous_was_token = false;
                continue;
            }
            if previous_was_token {
                if let Some(last) = input.joint.last_mut() {
                    *last = true;
                }
            }
            previous_was_token = true;
            input.kinds.push(token.kind);
            input.contextual.push(if token.kind == IDENT {
                SyntaxKind::from_contextual_keyword(&text[range])
            } else {
                None
            });
            input.ranges.push(range);
            input.joint.push(false);
        }
        let depth = input.kinds.iter().fold(0i64, |depth, kind| match kind {
            L_CURLY => depth + 1,
            R_CURLY => depth - 1,
            _ => depth,
        });
        input.braces_balanced = depth == 0;
        input
    }

    fn kind(&self, i: usize) -> SyntaxKind {
        self.kinds.get(i).copied().unwrap_or(EOF)
    }
}

/// One step of the tree to build.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Event {
    /// Start a node. `forward_parent` points (relatively) at a `Start` that must be opened
    /// before this one: the wrapper created by `precede`.
    Start {
        kind: SyntaxKind,
        forward_parent: Option<std::num::NonZeroU32>,
    },
    Finish,
    /// Consume `n_raw` lexer tokens (more than one for `>>`, `>=`, `>>=`) as one token `kind`.
    Token {
        kind: SyntaxKind,
        n_raw: u8,
    },
    /// A start that was abandoned or moved.
    Tombstone,
}

/// Deepest nesting of blocks, expressions and types the grammar descends into.
const MAX_DEPTH: u32 = 192;
/// Lookahead calls without progress after which the parser gives up (a grammar bug guard).
const MAX_STALL: u32 = 4096;

pub(crate) struct Parser<'i> {
    input: &'i Input<'i>,
    pos: usize,
    events: Vec<Event>,
    errors: Vec<SyntaxError>,
    depth: u32,
    stall: std::cell::Cell<u32>,
}

impl<'i> Parser<'i> {
    pub(crate) fn new(input: &'i Input<'i>) -> Parser<'i> {
        Parser {
            input,
            pos: 0,
            // A token and the starts and finishes of the nodes around it: about three events a
            // token (room left unused is never touched).
            events: Vec::with_capacity(input.kinds.len() * 4),
            errors: Vec::new(),
            depth: 0,
            stall: std::cell::Cell::new(0),
        }
    }

    pub(crate) fn finish(mut self) -> (Vec<Event>, Vec<SyntaxError>) {
        // Only a grammar bug (caught by the stall guard) leaves tokens unparsed: say so rather
        // than drop them silently (the tree builder keeps them in an ERROR node).
        if self.pos < self.input.kinds.len() {
            let start = self.input.ranges[self.pos].start();
            let range = TextRange::new(start, self.input.text_len.into());
            self.push_error(
                SyntaxErrorCode::UnexpectedToken,
                "the parser could not read the rest of the file".into(),
                range,
            );
        }
        (self.events, self.errors)
    }

    // ---- lookahead

    /// Kind of the current token; `EOF` at the end (or if the grammar stops making progress).
    pub(crate) fn current(&self) -> SyntaxKind {
        self.nth(0)
    }

    pub(crate) fn nth(&self, n: usize) -> SyntaxKind {
        let stall = self.stall.get() + 1;
        self.stall.set(stall);
        if stall > MAX_STALL {
            debug_assert!(false, "parser made no progress at token {}", self.pos);
            return EOF;
        }
        self.input.kind(self.pos + n)
    }

    /// Whether the current token is `kind`; `>=`, `>>` and `>>=` are recognised from joint `>`s.
    pub(crate) fn at(&self, kind: SyntaxKind) -> bool {
        self.nth_at(0, kind)
    }

    pub(crate) fn nth_at(&self, n: usize, kind: SyntaxKind) -> bool {
        let i = self.pos + n;
        let joint = |k: usize| self.input.joint.get(i + k).copied().unwrap_or(false);
        let kind_at = |k: usize| self.input.kind(i + k);
        match kind {
            GTEQ => self.nth(n) == R_ANGLE && joint(0) && kind_at(1) == EQ,
            SHR => self.nth(n) == R_ANGLE && joint(0) && kind_at(1) == R_ANGLE,
            SHREQ => self.nth(n) == R_ANGLE && joint(0) && kind_at(1) == R_ANGLE && joint(1) && kind_at(2) == EQ,
            _ if kind.is_contextual_keyword() => self.nth_at_contextual(n, kind),
            _ => self.nth(n) == kind,
        }
    }

    /// Kind `n` tokens ahead, for scans over a whole construct (not counted as a stall).
    pub(crate) fn peek(&self, n: usize) -> SyntaxKind {
        self.input.kind(self.pos + n)
    }

    pub(crate) fn at_ts(&self, set: TokenSet) -> bool {
        set.contains(self.current())
    }

    /// Whether the current token is the contextual keyword `kw`.
    pub(crate) fn at_contextual(&self, kw: SyntaxKind) -> bool {
        self.nth_at_contextual(0, kw)
    }

    pub(crate) fn nth_at_contextual(&self, n: usize, kw: SyntaxKind) -> bool {
        self.nth(n) == IDENT && self.input.contextual.get(self.pos + n).copied().flatten() == Some(kw)
    }

    /// The contextual keyword the current identifier spells, if any.
    pub(crate) fn current_contextual(&self) -> Option<SyntaxKind> {
        if self.current() == IDENT {
            self.input.contextual.get(self.pos).copied().flatten()
        } else {
            None
        }
    }

    /// Whether the current token can serve as a name: an identifier or a contextual keyword.
    pub(crate) fn at_name(&self) -> bool {
        self.at(IDENT)
    }

    pub(crate) fn nth_is_name(&self, n: usize) -> bool {
        self.nth(n) == IDENT
    }

    // ---- consuming

    fn push_token(&mut self, kind: SyntaxKind, n_raw: u8) {
        self.pos += n_raw as usize;
        self.stall.set(0);
        self.events.push(Event::Token { kind, n_raw });
    }

    /// Consumes the current token as `kind` (which the current token must be).
    pub(crate) fn bump(&mut self, kind: SyntaxKind) {
        let n_raw = match kind {
            GTEQ | SHR => 2,
            SHREQ => 3,
            _ => 1,
        };
        debug_assert!(self.at(kind), "bump({kind:?}) at {:?}", self.current());
        self.push_token(kind, n_raw);
    }

    /// Consumes the current token, whatever it is.
    pub(crate) fn bump_any(&mut self) {
        if self.current() != EOF {
            let kind = self.current();
            self.push_token(kind, 1);
        }
    }

    /// Consumes the current token as `kind` if it is one.
    pub(crate) fn eat(&mut self, kind: SyntaxKind) -> bool {
        if self.at(kind) {
            self.bump(kind);
            true
        } else {
            false
        }
    }

    /// Consumes `kind` or reports it missing right after the previous token, saying what it
    /// was for (`expected `;` after the field`).
    pub(crate) fn expect_with(&mut self, kind: SyntaxKind, what: &str) -> bool {
        if self.eat(kind) {
            return true;
        }
        self.error_missing(format!("expected {} {what}", kind.describe()));
        false
    }

    // ---- errors

    /// Range of the end of the previous token (where something is missing).
    fn missing_range(&self) -> TextRange {
        let end = match self.pos.checked_sub(1) {
            Some(prev) => self.input.ranges[prev].end(),
            None => 0.into(),
        };
        TextRange::empty(end)
    }

    /// Range of the current token (EOF: the end of the text).
    pub(crate) fn current_range(&self) -> TextRange {
        self.input.ranges.get(self.pos).copied().unwrap_or_else(|| TextRange::empty(self.input.text_len.into()))
    }

    fn push_error(&mut self, code: SyntaxErrorCode, message: String, range: TextRange) {
        // Several constructs unwinding at the same point would repeat one fault.
        if self.errors.last().is_some_and(|last| last.range == range) {
            return;
        }
        self.errors.push(SyntaxError::new(code, message, range));
    }

    /// Reports something missing just after the previous token.
    pub(crate) fn error_missing(&mut self, message: impl Into<String>) {
        let range = self.missing_range();
        self.push_error(SyntaxErrorCode::UnexpectedToken, message.into(), range);
    }

    /// Reports a missing closing delimiter just after the previous token.
    pub(crate) fn error_unclosed(&mut self, message: impl Into<String>) {
        let range = self.missing_range();
        self.push_error(SyntaxErrorCode::UnclosedDelimiter, message.into(), range);
    }

    /// Reports an error on the current token.
    pub(crate) fn error_here(&mut self, message: impl Into<String>) {
        let range = self.current_range();
        self.push_error(SyntaxErrorCode::UnexpectedToken, message.into(), range);
    }

    /// Reports the current token and every following one not in `recovery` (nor a closing
    /// delimiter) as one error, wrapped in one `ERROR` node. Stops before `recovery` tokens.
    pub(crate) fn err_recover(&mut self, message: &str, recovery: TokenSet) {
        self.err_recover_until(message, &|p: &Parser| p.at_ts(recovery));
    }

    /// Like [`Parser::err_recover`], stopping where `stop` holds (for contextual keywords).
    pub(crate) fn err_recover_until(&mut self, message: &str, stop: &dyn Fn(&Parser) -> bool) {
        self.err_expected_keyword(message, &[], stop);
    }

    /// Like [`Parser::err_recover_until`] where one of `keywords` was expected: a word that is
    /// a typo of one of them is told so (`clas`: "did you mean `class`?").
    pub(crate) fn err_expected_keyword(&mut self, message: &str, keywords: &[&str], stop: &dyn Fn(&Parser) -> bool) {
        let word = self.current_text();
        let typo =
            (self.current() == IDENT).then(|| crate::spelling::closest(word, keywords.iter().copied())).flatten();
        let describe = match typo {
            Some(keyword) => format!("{}; did you mean `{keyword}`?", self.current_description()),
            None => self.current_description(),
        };
        if self.at(EOF) {
            self.error_missing(message.to_string());
            return;
        }
        // The error is the token that was not expected; what is skipped after it is one ERROR
        // node with it, not part of the diagnostic's range (which stays on one line).
        let at = self.current_range();
        let m = self.start();
        let mut first = true;
        while !self.at(EOF) {
            if !first && (stop(self) || self.at(R_CURLY)) {
                break;
            }
            if self.at_ts(OPENERS) {
                self.skip_balanced();
            } else {
                self.bump_any();
            }
            first = false;
            if self.input.kind(self.pos.saturating_sub(1)) == SEMICOLON {
                break;
            }
        }
        m.complete(self, ERROR);
        self.push_error(SyntaxErrorCode::UnexpectedToken, format!("{message}, found {describe}"), at);
    }

    /// Reports and consumes the current token alone, in an `ERROR` node.
    pub(crate) fn err_and_bump(&mut self, message: &str) {
        let describe = self.current_description();
        let range = self.current_range();
        let m = self.start();
        self.bump_any();
        m.complete(self, ERROR);
        self.push_error(SyntaxErrorCode::UnexpectedToken, format!("{message}, found {describe}"), range);
    }

    /// How the current token reads in a message: `` `}` ``, `identifier `foo``.
    pub(crate) fn current_description(&self) -> String {
        let kind = self.current();
        match kind {
            IDENT => format!("`{}`", &self.input.text[self.current_range()]),
            INT_NUMBER | FLOAT_NUMBER => format!("number `{}`", &self.input.text[self.current_range()]),
            _ => kind.describe().to_string(),
        }
    }

    /// Consumes a balanced bracket group (or one token), iteratively, however deep.
    pub(crate) fn skip_balanced(&mut self) {
        let mut depth = 0usize;
        loop {
            let kind = self.current();
            if kind == EOF {
                return;
            }
            if OPENERS.contains(kind) {
                depth += 1;
            } else if CLOSERS.contains(kind) {
                depth = depth.saturating_sub(1);
            }
            self.bump_any();
            if depth == 0 {
                return;
            }
        }
    }

    /// Consumes everything up to (not including) the closing delimiter of the group the parser
    /// is in, iteratively, however deep the text nests.
    fn skip_to_enclosing_close(&mut self) {
        self.skip_balanced_until(|_| false);
    }

    /// Consumes tokens, nested groups whole, up to (not including) the first token outside any
    /// group it opened for which `stop` holds (an enclosing close always stops), or the end.
    /// Iterative, however deep the text nests.
    fn skip_balanced_until(&mut self, stop: impl Fn(SyntaxKind) -> bool) {
        let mut depth = 0usize;
        loop {
            let kind = self.current();
            if kind == EOF || (depth == 0 && (stop(kind) || CLOSERS.contains(kind))) {
                return;
            }
            if OPENERS.contains(kind) {
                depth += 1;
            } else if CLOSERS.contains(kind) {
                depth -= 1;
            }
            self.bump_any();
        }
    }

    /// Source text of the current token (empty at the end).
    /// Whether every `{` of the text has its `}`: then a declaration inside a body is nested
    /// on purpose, not the next one after a missing `}`.
    pub(crate) fn braces_balanced(&self) -> bool {
        self.input.braces_balanced
    }

    pub(crate) fn current_text(&self) -> &'i str {
        match self.input.ranges.get(self.pos) {
            Some(range) => &self.input.text[*range],
            None => "",
        }
    }

    // ---- nesting

    /// Whether a chain `links` long (`a + b + …`, `a.b.c…`, `f()()…`: each link nests the tree one
    /// level deeper) at the current nesting passes the depth limit.
    pub(crate) fn chain_too_deep(&self, links: usize) -> bool {
        self.depth as usize + links >= MAX_DEPTH as usize
    }

    /// Past the depth limit inside a chain: reports it and keeps the rest of the expression (up
    /// to `;`, `,`, `:`, `=>`, `{` or the enclosing close) in an ERROR node, iteratively.
    pub(crate) fn skip_deep_chain(&mut self) {
        let range = self.current_range();
        let m = self.start();
        self.skip_balanced_until(|kind| matches!(kind, SEMICOLON | COMMA | COLON | FAT_ARROW | L_CURLY));
        m.complete(self, ERROR);
        self.push_error(
            SyntaxErrorCode::NestingTooDeep,
            format!("an expression chained deeper than {MAX_DEPTH} levels is not analysed"),
            range,
        );
    }

    /// Enters a nested construct. Past the depth limit it reports the nesting, keeps the
    /// nested text in an `ERROR` node and returns `false`: the caller must not descend.
    pub(crate) fn enter(&mut self) -> bool {
        if self.depth >= MAX_DEPTH {
            let range = self.current_range();
            let m = self.start();
            self.skip_to_enclosing_close();
            m.complete(self, ERROR);
            self.push_error(
                SyntaxErrorCode::NestingTooDeep,
                format!("nesting deeper than {MAX_DEPTH} levels is not analysed"),
                range,
            );
            return false;
        }
        self.depth += 1;
        true
    }

    pub(crate) fn leave(&mut self) {
        self.depth -= 1;
    }

    // ---- markers

    pub(crate) fn start(&mut self) -> Marker {
        let pos = self.events.len() as u32;
        self.events.push(Event::Tombstone);
        Marker { pos, bomb: DropBomb::new() }
    }
}

/// Tokens that open a bracket group.
pub(crate) const OPENERS: TokenSet = TokenSet::new(&[L_PAREN, L_CURLY, L_BRACK]);
/// Tokens that close a bracket group.
pub(crate) const CLOSERS: TokenSet = TokenSet::new(&[R_PAREN, R_CURLY, R_BRACK]);

/// Panics in debug builds if dropped while armed: a marker that was neither completed nor
/// abandoned would lose a node.
struct DropBomb {
    armed: bool,
}

impl DropBomb {
    fn new() -> Self {
        DropBomb { armed: true }
    }

    fn defuse(&mut self) {
        self.armed = false;
    }
}

impl Drop for DropBomb {
    fn drop(&mut self) {
        if self.armed && !std::thread::panicking() {
            debug_assert!(false, "a parser Marker was dropped without complete/abandon");
        }
    }
}

/// An open node.
pub(crate) struct Marker {
    pos: u32,
    bomb: DropBomb,
}

impl Marker {
    /// Closes the node as `kind`.
    pub(crate) fn complete(mut self, p: &mut Parser, kind: SyntaxKind) -> CompletedMarker {
        self.bomb.defuse();
        let idx = self.pos as usize;
        if let Event::Tombstone = p.events[idx] {
            p.events[idx] = Event::Start { kind, forward_parent: None };
        }
        p.events.push(Event::Finish);
        CompletedMarker { pos: self.pos }
    }

    /// Drops the node; its children go to the parent.
    pub(crate) fn abandon(mut self, p: &mut Parser) {
        self.bomb.defuse();
        let idx = self.pos as usize;
        if idx == p.events.len() - 1 {
            if let Event::Tombstone = p.events[idx] {
                p.events.pop();
            }
        }
    }
}

/// A finished node, which can still be wrapped by a new parent.
#[derive(Clone, Copy)]
pub(crate) struct CompletedMarker {
    pos: u32,
}

impl CompletedMarker {
    /// Starts a node that will contain this one.
    pub(crate) fn precede(self, p: &mut Parser) -> Marker {
        let new = p.start();
        if let Event::Start { forward_parent, .. } = &mut p.events[self.pos as usize] {
            // The wrapper starts later than the node it wraps: the distance is never zero.
            *forward_parent = std::num::NonZeroU32::new(new.pos - self.pos);
        }
        new
    }
}
