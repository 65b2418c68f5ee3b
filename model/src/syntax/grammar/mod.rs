//! The GU-DSL grammar: one recursive-descent function per construct, emitting parser events.
//!
//! `docs/grammar.md` is the grammar in EBNF; each module here implements one part of it.

mod activity;
mod class_diagram;
mod components;
mod expressions;
mod statements;
mod types;

use std::fmt::Display;

use super::{
    parser::{CompletedMarker, Event, Input, Parser},
    token_set::TokenSet,
    SyntaxError, SyntaxKind,
    SyntaxKind::*,
};

/// Parses a whole document.
pub(crate) fn source_file(input: &Input) -> (Vec<Event>, Vec<SyntaxError>) {
    let mut p = Parser::new(input);
    let m = p.start();
    while !p.at(EOF) {
        if p.at(IMPORT_KW) {
            import(&mut p);
        } else if !diagram(&mut p) {
            p.err_expected_keyword(
                "expected a diagram (`ClassDiagram`, `ActivityDiagram`, `ComponentDiagram` or \
                 `ComponentInstanceDiagram`)",
                &["ClassDiagram", "ActivityDiagram", "ComponentDiagram", "ComponentInstanceDiagram"],
                &at_diagram_start,
            );
        }
    }
    m.complete(&mut p, SOURCE_FILE);
    p.finish()
}

/// Whether a diagram header starts here.
pub(super) fn at_diagram_start(p: &Parser) -> bool {
    matches!(
        p.current_contextual(),
        Some(CLASS_DIAGRAM_KW | ACTIVITY_DIAGRAM_KW | COMPONENT_DIAGRAM_KW | COMPONENT_INSTANCE_DIAGRAM_KW)
    )
}

/// Parses a diagram of any kind, if one starts here.
pub(super) fn diagram(p: &mut Parser) -> bool {
    match p.current_contextual() {
        Some(CLASS_DIAGRAM_KW) => nested(p, class_diagram::class_diagram),
        Some(ACTIVITY_DIAGRAM_KW) => nested(p, activity::activity_diagram),
        Some(COMPONENT_DIAGRAM_KW) => nested(p, components::component_diagram),
        Some(COMPONENT_INSTANCE_DIAGRAM_KW) => nested(p, components::component_instance_diagram),
        _ => return false,
    }
    true
}

/// Runs `f` one nesting level deeper (or skips the nested text past the depth limit).
pub(super) fn nested(p: &mut Parser, f: fn(&mut Parser)) {
    if p.enter() {
        f(p);
        p.leave();
    }
}

/// `import A.B.*;` or `import "<QImage>";`
pub(super) fn import(p: &mut Parser) {
    let m = p.start();
    p.bump(IMPORT_KW);
    if p.at(STRING) {
        let lit = p.start();
        p.bump(STRING);
        lit.complete(p, LITERAL);
    } else if p.at_name() {
        path(p);
        if p.at(DOT) && p.nth(1) == STAR {
            p.bump(DOT);
            p.bump(STAR);
        }
    } else {
        p.error_here("expected a qualified name or a header string after `import`");
    }
    p.expect_with(SEMICOLON, "after the import");
    m.complete(p, IMPORT);
}

/// A defining name.
pub(super) fn name(p: &mut Parser, what: impl Display) -> bool {
    if p.at_name() {
        let m = p.start();
        p.bump(IDENT);
        m.complete(p, NAME);
        true
    } else if p.current().is_keyword() && matches!(p.nth(1), SEMICOLON | L_PAREN | EQ | COMMA | R_PAREN | L_CURLY) {
        // `public int class;`: the word was meant as the name; it is reported and read as one
        // would, so what follows parses as written.
        let message = format!("`{}` is a keyword, so it cannot be {what}: rename it", p.current_text());
        p.error_here(message);
        let m = p.start();
        p.bump_any();
        m.complete(p, ERROR);
        false
    } else {
        p.error_missing(format!("expected {what}"));
        false
    }
}

/// A name that refers to something defined elsewhere.
pub(super) fn name_ref(p: &mut Parser) {
    let m = p.start();
    p.bump(IDENT);
    m.complete(p, NAME_REF);
}

/// A (possibly qualified) name: `A.B.C`. Stops before `.*` and before a `.` not followed by a
/// name. The caller checks `at_name` first.
pub(super) fn path(p: &mut Parser) -> CompletedMarker {
    let m = p.start();
    name_ref(p);
    while p.at(DOT) && p.nth_is_name(1) {
        p.bump(DOT);
        name_ref(p);
    }
    m.complete(p, PATH)
}

/// A qualified name, or an error saying what was expected.
pub(super) fn path_or_error(p: &mut Parser, what: &str) -> bool {
    if p.at_name() {
        path(p);
        true
    } else {
        p.error_missing(format!("expected {what}"));
        false
    }
}

/// `[A.B(x = y), C]`: attribute usages before a declaration.
pub(super) fn attribute_list(p: &mut Parser) {
    let m = p.start();
    p.bump(L_BRACK);
    while !p.at(EOF) && !p.at(R_BRACK) {
        if p.at_name() {
            let use_ = p.start();
            path(p);
            if p.at(L_PAREN) {
                named_arg_list(p);
            }
            use_.complete(p, ATTRIBUTE_USE);
        } else if p.at(COMMA) {
            p.error_here("expected an attribute name");
        } else {
            break;
        }
        if !p.eat(COMMA) {
            break;
        }
    }
    if !p.eat(R_BRACK) {
        p.error_unclosed("expected `]` to close the attribute list");
    }
    m.complete(p, ATTRIBUTE_LIST);
}

/// `(name = value, …)`: attribute arguments and instance field values.
pub(super) fn named_arg_list(p: &mut Parser) {
    let m = p.start();
    p.bump(L_PAREN);
    while !p.at(EOF) && !p.at(R_PAREN) {
        if p.at_name() {
            let arg = p.start();
            name_ref(p);
            if p.expect_with(EQ, "between the field name and its value") {
                expressions::expr_or_error(p);
            }
            arg.complete(p, NAMED_ARG);
        } else {
            p.err_recover("expected `name = value`", TokenSet::new(&[COMMA, R_PAREN, SEMICOLON]));
            if p.at(SEMICOLON) {
                break;
            }
        }
        if !p.at(R_PAREN) && !p.expect_with(COMMA, "between field values") && !p.at_name() {
            break;
        }
    }
    if !p.eat(R_PAREN) {
        p.error_unclosed("expected `)` to close the field values");
    }
    m.complete(p, NAMED_ARG_LIST);
}

/// Visibility and qualifier keywords.
const VISIBILITY: TokenSet = TokenSet::new(&[PUBLIC_KW, PROTECTED_KW, PRIVATE_KW]);

/// Whether the current token is a field/parameter qualifier (`const`, `ref`, `global`, …).
/// A contextual qualifier counts only when a type follows it, so `out x` stays a type and name.
pub(super) fn at_qualifier(p: &Parser) -> bool {
    match p.current() {
        CONST_KW | REF_KW => true,
        IDENT => {
            matches!(p.current_contextual(), Some(GLOBAL_KW | SHARED_KW | OUT_KW | READ_KW | WRITE_KW | STATIC_KW))
                && (types::nth_at_type_keyword(p, 1)
                    || (p.nth(1) == IDENT && matches!(p.nth(2), IDENT | L_ANGLE | DOT | L_BRACK)))
        }
        _ => false,
    }
}

/// `public abstract const …`: visibility, `abstract` and qualifiers, in one MODIFIERS node.
pub(super) fn modifiers(p: &mut Parser) {
    if !(p.at_ts(VISIBILITY) || p.at(ABSTRACT_KW) || at_qualifier(p)) {
        return;
    }
    let m = p.start();
    loop {
        if p.at_ts(VISIBILITY) || p.at(ABSTRACT_KW) || p.at(CONST_KW) || p.at(REF_KW) {
            p.bump_any();
        } else if at_qualifier(p) {
            let kind = p.current_contextual().unwrap_or(IDENT);
            p.bump(kind);
        } else {
            break;
        }
    }
    m.complete(p, MODIFIERS);
}

/// Consumes `}` closing `what`, or reports that it is missing.
pub(super) fn close_curly(p: &mut Parser, what: impl Display) {
    if !p.eat(R_CURLY) {
        p.error_unclosed(format!("expected `}}` to close {what}"));
    }
}

/// Consumes `{` opening `what`, or reports it missing. Returns whether to parse the body:
/// after a missing `{` the body is parsed all the same (its `}` usually follows), so one
/// forgotten brace gives one error, not one per line of the body.
pub(super) fn open_curly(p: &mut Parser, what: impl Display) -> bool {
    if p.eat(L_CURLY) {
        return true;
    }
    p.error_missing(format!("expected `{{` to open {what}"));
    !p.at(EOF)
}

/// `Keyword Name` opening a diagram; returns how the diagram reads in messages.
pub(super) fn diagram_header<'i>(p: &mut Parser<'i>, keyword: SyntaxKind, what: &'static str) -> Described<'i> {
    p.bump(keyword);
    let described = describe_named(p, what);
    name(p, format_args!("a name for the {what}"));
    described
}

/// The construct at the current position as messages name it ("class `Image`"; "class" where
/// no name follows).
pub(super) fn describe_named<'i>(p: &Parser<'i>, what: &'static str) -> Described<'i> {
    Described { what, name: p.at_name().then(|| p.current_text()) }
}

/// How messages name a construct ("node `init`"): kept as its parts and written out only when
/// a message needs it, so parsing a valid file formats no message.
#[derive(Debug, Clone, Copy)]
pub(super) struct Described<'i> {
    what: &'static str,
    name: Option<&'i str>,
}

impl<'i> Described<'i> {
    /// `what` named by the text at the current position, a name or not (`node `3``).
    pub(super) fn current(p: &Parser<'i>, what: &'static str) -> Described<'i> {
        Described { what, name: Some(p.current_text()) }
    }
}

impl Display for Described<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.name {
            Some(name) => write!(f, "{} `{name}`", self.what),
            None => f.write_str(self.what),
        }
    }
}
