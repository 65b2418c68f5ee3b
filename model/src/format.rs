//! The formatter: canonical indentation, line breaks and spacing for a GU-DSL document,
//! keeping every comment and at most one blank line where the author left blank lines.
//!
//! It re-emits the document's tokens. Declarations, members, statements, nodes, transitions,
//! ports and bindings start on their own line; blocks indent by four spaces; operators are
//! spaced as in the dissertation's listings. Line breaks the author wrote inside parentheses
//! (long argument lists) are kept as continuation lines. A document with syntax errors is not
//! formatted: `format` returns `None` rather than guess around the broken text. Line endings
//! follow the document's first line (`\n`, `\r\n` or `\r`), as rustfmt's `Auto` does.

use crate::{
    syntax::{SyntaxKind, SyntaxKind::*, SyntaxToken},
    text::{line_breaks, line_ending, with_line_ending},
    Parse,
};

const INDENT: &str = "    ";

/// Nodes that start on a line of their own: declarations (but enum values, listed on one line)
/// and statements (but empty ones).
fn starts_line(kind: SyntaxKind) -> bool {
    (kind.is_item() && kind != ENUM_VALUE) || (kind.is_stmt() && kind != EMPTY_STMT) || kind == SWITCH_CASE
}

/// The outermost node that `token` is the first token of.
fn started_node(token: &SyntaxToken) -> Option<SyntaxKind> {
    let mut result = None;
    let mut node = token.parent();
    while let Some(n) = node {
        if n.first_token().as_ref() != Some(token) {
            break;
        }
        if starts_line(n.kind()) {
            // VAR_DECLs inside loop headers and `for` stay inline.
            let in_header = n.ancestors().skip(1).any(|a| matches!(a.kind(), LOOP_HEADER | FOR_STMT | LOOP_WINDOW_DIM))
                && n.kind() == VAR_DECL;
            // A block that is the body of a construct stays on the construct's line.
            let body_block =
                n.kind() == BLOCK && n.parent().is_some_and(|p| p.kind() != BLOCK && p.kind() != NODE_BODY);
            if !in_header && !body_block {
                result = Some(n.kind());
            }
        }
        node = n.parent();
    }
    result
}

fn parent_kind(token: &SyntaxToken) -> SyntaxKind {
    token.parent().map_or(SOURCE_FILE, |p| p.kind())
}

fn is_keyword_like(kind: SyntaxKind) -> bool {
    kind.is_keyword()
}

/// Whether a space separates `prev` and `next` on one line.
fn space_between(prev: &SyntaxToken, next: &SyntaxToken) -> bool {
    let (p, n) = (prev.kind(), next.kind());
    let (pp, np) = (parent_kind(prev), parent_kind(next));
    match (p, n) {
        (_, SEMICOLON | COMMA | R_PAREN | DOT | COLON2) => false,
        (L_PAREN | DOT | COLON2 | BANG | TILDE, _) => false,
        (L_BRACK, _) => false,
        (_, R_BRACK) => false,
        (_, COLON) if matches!(np, SWITCH_CASE | SWITCH_STMT) => false,
        // Type arguments and template parameters: `A<B, C>`.
        (_, L_ANGLE) | (L_ANGLE, _)
            if matches!(np, TYPE_ARGS | TEMPLATE_PARAMS) || matches!(pp, TYPE_ARGS | TEMPLATE_PARAMS) =>
        {
            false
        }
        (_, R_ANGLE) if matches!(np, TYPE_ARGS | TEMPLATE_PARAMS) => false,
        (R_ANGLE, L_PAREN | L_BRACK) if matches!(pp, TYPE_ARGS) => false,
        // Prefix operators bind to their operand.
        (MINUS | PLUS | PLUS2 | MINUS2, _) if pp == PREFIX_EXPR => false,
        (_, PLUS2 | MINUS2) if np == POSTFIX_EXPR => false,
        // `(float)x`
        (R_PAREN, _) if pp == CAST_EXPR => false,
        // `import A.*`
        (_, STAR) if np == IMPORT => false,
        // Calls, parameter lists, headers: `f(`, `if(`, `loop(`, `new T(`, `T[n]`, `a[i]`.
        (IDENT | R_PAREN | R_BRACK | R_ANGLE, L_PAREN) => false,
        (k, L_PAREN) if is_keyword_like(k) && !matches!(k, RETURN_KW | AS_KW | CALL_KW) => false,
        (_, L_BRACK) if matches!(np, INDEX_EXPR | NEW_EXPR | TYPE_REF) => false,
        _ => true,
    }
}

/// Formats a parsed document; `None` if it has syntax errors. The output keeps the
/// document's line terminator (that of its first line) and its byte-order mark.
pub fn format(parse: &Parse) -> Option<String> {
    if !parse.errors().is_empty() {
        return None;
    }
    let root = parse.syntax_node();
    let mut printer = Printer::default();
    let mut eol = None;
    let bom = root.text().char_at(0.into()) == Some('\u{feff}');
    for token in root.descendants_with_tokens().filter_map(|e| e.into_token()) {
        if eol.is_none() && token.text().contains(['\n', '\r']) {
            eol = Some(line_ending(token.text()));
        }
        printer.token(token);
    }
    let mut out = with_line_ending(&printer.finish(), eol.unwrap_or("\n"));
    if bom {
        out.insert(0, '\u{feff}');
    }
    Some(out)
}

/// The formatted text so far and where the next token goes.
#[derive(Default)]
struct Printer {
    out: String,
    /// Open `{`s.
    depth: usize,
    /// Open `(`s and `[`s: a line broken inside them is a continuation.
    paren_depth: usize,
    prev: Option<SyntaxToken>,
    /// Newlines in the whitespace just before the current token.
    newlines_before: usize,
    at_line_start: bool,
    force_newline: bool,
    /// Per open `{`: whether a line break happened inside it (else its `}` stays on the line).
    broken: Vec<bool>,
}

impl Printer {
    /// Writes `token` after what separates it from the previous one.
    fn token(&mut self, token: SyntaxToken) {
        let kind = token.kind();
        if kind == WHITESPACE {
            self.newlines_before = line_breaks(token.text());
            return;
        }
        match kind {
            R_CURLY => self.depth = self.depth.saturating_sub(1),
            R_PAREN | R_BRACK => self.paren_depth = self.paren_depth.saturating_sub(1),
            _ => {}
        }
        self.separate(&token);
        self.out.push_str(token.text().trim_end());
        self.at_line_start = false;
        self.force_newline = false;
        self.newlines_before = 0;
        self.after(&token);
        self.prev = Some(token);
    }

    /// A line break (with the indentation of the new line), a space or nothing before `token`.
    fn separate(&mut self, token: &SyntaxToken) {
        let kind = token.kind();
        let is_comment = matches!(kind, LINE_COMMENT | BLOCK_COMMENT);
        let prev_kind = self.prev.as_ref().map(|p| p.kind());
        let empty_block = kind == R_CURLY && prev_kind == Some(L_CURLY);
        let inline_block = kind == R_CURLY && self.broken.last().is_some_and(|b| !b);
        let line_level = !is_comment && started_node(token).is_some();
        // Braces of a body that spans lines go on their own line, as in the dissertation.
        let own_line_brace = kind == L_CURLY && body_breaks(token);
        let started = self.prev.is_some();
        let mut wants_newline = self.force_newline
            || (line_level && !self.at_line_start && started)
            || (kind == R_CURLY && !inline_block)
            || own_line_brace
            || (is_comment && self.newlines_before > 0 && started)
            // A block comment (a doc comment above a declaration) keeps the line break after it.
            || (prev_kind == Some(BLOCK_COMMENT) && self.newlines_before > 0)
            || (self.paren_depth > 0 && self.newlines_before > 0 && !is_comment && started);
        if kind == R_CURLY && inline_block && !self.force_newline {
            wants_newline = false;
        }
        if wants_newline && started {
            // Keep one blank line where the author left at least one (not right after `{`).
            let blank = self.newlines_before >= 2 && prev_kind != Some(L_CURLY) && kind != R_CURLY;
            self.newline(if blank { 2 } else { 1 });
            self.at_line_start = true;
            if let Some(last) = self.broken.last_mut() {
                *last = true;
            }
        }
        if self.at_line_start {
            if started || !self.out.is_empty() {
                let level = self.depth + usize::from(self.paren_depth > 0) + usize::from(in_flat_member(token));
                for _ in 0..level {
                    self.out.push_str(INDENT);
                }
            }
        } else if let Some(p) = &self.prev {
            if is_comment || empty_block || space_between(p, token) {
                self.out.push(' ');
            }
        }
    }

    /// What `token` opens, closes or ends.
    fn after(&mut self, token: &SyntaxToken) {
        match token.kind() {
            L_CURLY => {
                self.depth += 1;
                self.broken.push(false);
            }
            L_PAREN | L_BRACK => self.paren_depth += 1,
            LINE_COMMENT => self.force_newline = true,
            // A `}` ends its line, except before `;`, `else` and `loop` (of `do … loop`).
            R_CURLY => {
                let inner_broken = self.broken.pop().unwrap_or(false);
                if let Some(last) = self.broken.last_mut() {
                    *last |= inner_broken;
                }
                if let Some(next) = token.next_token().and_then(|t| next_significant(&t)) {
                    if !matches!(next.kind(), SEMICOLON | LOOP_KW | COMMA | R_PAREN) {
                        self.force_newline = true;
                    }
                }
            }
            // The `;` of a statement or declaration ends its line (not inside headers).
            SEMICOLON if self.paren_depth == 0 => self.force_newline = true,
            // Attribute lists stand on their own line above the declaration.
            R_BRACK
                if parent_kind(token) == ATTRIBUTE_LIST
                    && token.parent().and_then(|p| p.parent()).is_some_and(|g| g.kind() != ENUM_VALUE) =>
            {
                self.force_newline = true
            }
            _ => {}
        }
    }

    /// Ends the line (trailing spaces dropped) `count` times.
    fn newline(&mut self, count: usize) {
        while self.out.ends_with(' ') {
            self.out.pop();
        }
        for _ in 0..count {
            self.out.push('\n');
        }
    }

    /// The text with exactly one final newline and no trailing blank lines (empty for none).
    fn finish(mut self) -> String {
        self.newline(1);
        while self.out.ends_with("\n\n") {
            self.out.pop();
        }
        if self.out == "\n" {
            self.out.clear();
        }
        self.out
    }
}

/// Whether the braced body `open` starts holds something that goes on a line of its own.
fn body_breaks(open: &SyntaxToken) -> bool {
    let Some(owner) = open.parent() else { return false };
    let start = open.text_range().end();
    owner.descendants_with_tokens().any(|element| {
        element.text_range().start() >= start
            && match element {
                rowan::NodeOrToken::Node(node) => starts_line(node.kind()),
                rowan::NodeOrToken::Token(token) => matches!(token.kind(), LINE_COMMENT),
            }
    })
}

fn next_significant(token: &SyntaxToken) -> Option<SyntaxToken> {
    let mut t = Some(token.clone());
    while let Some(current) = t {
        if !current.kind().is_trivia() {
            return Some(current);
        }
        t = current.next_token();
    }
    None
}

/// Whether `token` is in a port instance or binding written after its instance without braces
/// (Listing 28's flat form): indented one level more than the instance, as if in its body.
fn in_flat_member(token: &SyntaxToken) -> bool {
    let member = token.parent_ancestors().find(|n| matches!(n.kind(), PORT_INSTANCE | BINDING));
    member.is_some_and(|m| crate::ast::ComponentInstance::of_flat_member(&m).is_some())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(text: &str) -> String {
        format(&crate::parse(text)).expect("no syntax errors")
    }

    #[test]
    fn canonical_layout() {
        let input = "ClassDiagram D{  // the diagram\n[A.B(x=1)] public class C extends B{public int x=a+b*2;\n\n\n public void m(int a,int b){ if(a<b){x=-a;}else{x=b;}; for(i = 0:1:i<a){ } } }\npublic enum E { A, B = 2 }\n}\n";
        let expected = "ClassDiagram D\n{ // the diagram\n    [A.B(x = 1)]\n    public class C extends B\n    {\n        public int x = a + b * 2;\n\n        public void m(int a, int b)\n        {\n            if(a < b)\n            {\n                x = -a;\n            }\n            else\n            {\n                x = b;\n            };\n            for(i = 0 : 1 : i < a) { }\n        }\n    }\n    public enum E { A, B = 2 }\n}\n";
        assert_eq!(fmt(input), expected);
        assert_eq!(fmt(expected), expected, "idempotent");
    }

    #[test]
    fn activity_and_components() {
        let input = "ActivityDiagram Ad(int n),owner D.C{\npublic int i;\nswimlane L{start S{=>work(n);}\naction work(int k){var int x=k;[x>0]=>work(x);[]=>f;}\nloopWindow w(var int u=-1,var int v=-1;u<1,v<1;u=u+1,v=v+1){=>f;}\nfinal f;}}\nComponentDiagram Cd{source D.C{port P(provider p:I);[L source P.p==>target Q.q]}}\n";
        let out = fmt(input);
        assert!(
            out.contains("    swimlane L\n    {\n        start S\n        {\n            => work(n);\n        }\n"),
            "{out}"
        );
        assert!(out.contains("            [x > 0] => work(x);\n            [] => f;\n"), "{out}");
        assert!(
            out.contains("loopWindow w(var int u = -1, var int v = -1; u < 1, v < 1; u = u + 1, v = v + 1)\n"),
            "{out}"
        );
        assert!(out.contains("        port P(provider p : I);\n        [L source P.p ==> target Q.q]\n"), "{out}");
        assert_eq!(fmt(&out), out, "idempotent");
    }

    #[test]
    fn a_comment_on_its_own_lines_keeps_the_declaration_below_it() {
        let input = "ClassDiagram D\n{\n    /** A class\n        of two lines. */\n    public class C\n    {\n        /** m */\n        public void m(); /* after */ public void n();\n    }\n}\n";
        let expected = "ClassDiagram D\n{\n    /** A class\n        of two lines. */\n    public class C\n    {\n        /** m */\n        public void m();\n        /* after */ public void n();\n    }\n}\n";
        assert_eq!(fmt(input), expected);
        assert_eq!(fmt(expected), expected);
    }

    #[test]
    fn line_endings_and_byte_order_mark_are_kept() {
        let lf = &fmt(
            "ClassDiagram D\n{\n    /* one\n       two */\n    public class C { } // c\n\n    public class E { }\n}\n",
        );
        assert!(lf.contains("/* one\n       two */"), "{lf}");
        for eol in ["\r\n", "\r"] {
            let other = lf.replace('\n', eol);
            assert_eq!(fmt(&other), other, "{eol:?}");
        }
        // Mixed: the first line decides, everywhere (inside block comments too).
        assert_eq!(fmt(&lf.replacen('\n', "\r\n", 1)), lf.replace('\n', "\r\n"));
        let bom = format!("\u{feff}{lf}");
        assert_eq!(fmt(&bom), bom);
    }

    #[test]
    fn flat_instance_members_are_indented_as_in_a_body() {
        let input = "ComponentInstanceDiagram D\n{\nA instantiates X.C(w=1)\nP : Q(provider c=I());\n[source P.c==>target B.R.d]\nB instantiates X.D()\n}\n";
        let expected = "ComponentInstanceDiagram D\n{\n    A instantiates X.C(w = 1)\n        P : Q(provider c = I());\n        [source P.c ==> target B.R.d]\n    B instantiates X.D()\n}\n";
        assert_eq!(fmt(input), expected);
    }

    #[test]
    fn broken_documents_are_not_formatted() {
        assert!(format(&crate::parse("ClassDiagram D { class C { int x }")).is_none());
    }
}
