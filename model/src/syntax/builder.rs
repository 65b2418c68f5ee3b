//! Tree builder: replays parser events over the lexer's tokens into a lossless rowan green tree.
//!
//! Trivia (whitespace, comments) is placed here, not by the grammar: comments directly above a
//! declaration (no blank line between) become part of that declaration's node, so moving or
//! deleting the declaration in a graph edit keeps its comments with it. Whatever the grammar did
//! not consume ends in an `ERROR` node, so the tree always holds every byte.

use rowan::{GreenNode, GreenNodeBuilder};

use super::{lexer::LexedText, parser::Event, SyntaxKind, SyntaxKind::*};

pub(crate) fn build_tree(text: &str, lexed: &LexedText, mut events: Vec<Event>) -> GreenNode {
    let mut sink = Sink { text, lexed, token: 0, offset: 0, builder: GreenNodeBuilder::new(), depth: 0 };
    let mut forward_parents = Vec::new();
    for i in 0..events.len() {
        match std::mem::replace(&mut events[i], Event::Tombstone) {
            Event::Start { kind, forward_parent } => {
                // Open the chain of wrappers created by `precede`, outermost first.
                forward_parents.push(kind);
                let mut idx = i;
                let mut fp = forward_parent;
                while let Some(delta) = fp {
                    idx += delta.get() as usize;
                    fp = match std::mem::replace(&mut events[idx], Event::Tombstone) {
                        Event::Start { kind, forward_parent } => {
                            forward_parents.push(kind);
                            forward_parent
                        }
                        _ => None,
                    };
                }
                for kind in forward_parents.drain(..).rev() {
                    sink.start_node(kind);
                }
            }
            Event::Finish => sink.finish_node(),
            Event::Token { kind, n_raw } => sink.token(kind, n_raw),
            Event::Tombstone => {}
        }
    }
    sink.finish()
}

struct Sink<'a> {
    text: &'a str,
    lexed: &'a LexedText,
    /// Next raw token to place.
    token: usize,
    offset: usize,
    builder: GreenNodeBuilder<'static>,
    depth: usize,
}

impl Sink<'_> {
    fn raw_kind(&self, i: usize) -> SyntaxKind {
        self.lexed.tokens.get(i).map_or(EOF, |t| t.kind)
    }

    fn emit_raw(&mut self, kind: SyntaxKind) {
        let len = self.lexed.tokens[self.token].len as usize;
        self.builder.token(kind.into(), &self.text[self.offset..self.offset + len]);
        self.offset += len;
        self.token += 1;
    }

    fn eat_trivia(&mut self, max: usize) {
        let mut n = 0;
        while n < max && self.raw_kind(self.token).is_trivia() {
            self.emit_raw(self.raw_kind(self.token));
            n += 1;
        }
    }

    fn start_node(&mut self, kind: SyntaxKind) {
        if self.depth == 0 {
            // The root starts before any trivia.
            self.builder.start_node(kind.into());
            self.depth += 1;
            return;
        }
        let n_trivia = (self.token..).take_while(|&i| self.raw_kind(i).is_trivia()).count();
        let attached = if kind.is_item() { self.n_attached_trivia(n_trivia) } else { 0 };
        self.eat_trivia(n_trivia - attached);
        self.builder.start_node(kind.into());
        self.depth += 1;
    }

    /// How many of the `n` trivia tokens ahead belong to the node starting after them: the
    /// comments (and whitespace between them) not separated from the node by a blank line.
    fn n_attached_trivia(&self, n: usize) -> usize {
        let mut attached = 0;
        for back in (0..n).rev() {
            let i = self.token + back;
            match self.raw_kind(i) {
                WHITESPACE => {
                    let start: usize =
                        self.offset + self.lexed.tokens[self.token..i].iter().map(|t| t.len as usize).sum::<usize>();
                    let ws = &self.text[start..start + self.lexed.tokens[i].len as usize];
                    if crate::text::line_breaks(ws) >= 2 {
                        break;
                    }
                }
                LINE_COMMENT | BLOCK_COMMENT => attached = n - back,
                _ => break,
            }
        }
        attached
    }

    fn finish_node(&mut self) {
        if self.depth == 1 {
            // Leave the root open: `finish` places what is left first.
            return;
        }
        self.builder.finish_node();
        self.depth -= 1;
    }

    fn token(&mut self, kind: SyntaxKind, n_raw: u8) {
        self.eat_trivia(usize::MAX);
        if n_raw == 1 {
            self.emit_raw(kind);
            return;
        }
        // A composed token (`>=`, `>>`, `>>=`): one tree token spanning several raw ones.
        let len: usize =
            self.lexed.tokens[self.token..self.token + n_raw as usize].iter().map(|t| t.len as usize).sum();
        self.builder.token(kind.into(), &self.text[self.offset..self.offset + len]);
        self.offset += len;
        self.token += n_raw as usize;
    }

    fn finish(mut self) -> GreenNode {
        if self.depth == 0 {
            self.builder.start_node(SOURCE_FILE.into());
            self.depth = 1;
        }
        // Anything the grammar left unconsumed: trivia stays trivia, tokens go into ERROR.
        while self.token < self.lexed.tokens.len() {
            let kind = self.raw_kind(self.token);
            if kind.is_trivia() {
                self.emit_raw(kind);
            } else {
                self.builder.start_node(ERROR.into());
                while self.token < self.lexed.tokens.len() && !self.raw_kind(self.token).is_trivia() {
                    self.emit_raw(self.raw_kind(self.token));
                }
                self.builder.finish_node();
            }
        }
        while self.depth > 0 {
            self.builder.finish_node();
            self.depth -= 1;
        }
        self.builder.finish()
    }
}
