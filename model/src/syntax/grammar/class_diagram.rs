//! Class diagrams: classes, interfaces, enums, attribute definitions and their members.

use super::*;

/// `ClassDiagram Name { … }`
pub(super) fn class_diagram(p: &mut Parser) {
    let m = p.start();
    let what = diagram_header(p, CLASS_DIAGRAM_KW, "class diagram");
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            class_diagram_item(p);
        }
        close_curly(p, what);
    }
    m.complete(p, CLASS_DIAGRAM);
}

/// What a declaration in a class diagram or class body is, judged past its attribute list,
/// visibility and `abstract`.
#[derive(PartialEq, Eq, Clone, Copy)]
enum DeclKind {
    Class,
    Interface,
    Enum,
    AttributeDef,
    Other,
}

fn decl_kind(p: &Parser) -> DeclKind {
    let mut n = 0;
    // Skip attribute lists, balanced.
    while p.peek(n) == L_BRACK {
        let mut depth = 0usize;
        loop {
            match p.peek(n) {
                EOF => return DeclKind::Other,
                // An attribute list missing its `]`: the declaration starts here.
                PUBLIC_KW | PROTECTED_KW | PRIVATE_KW | ABSTRACT_KW | CLASS_KW | INTERFACE_KW | ENUM_KW
                | ATTRIBUTE_KW | L_CURLY | R_CURLY | SEMICOLON
                    if depth == 1 =>
                {
                    break
                }
                L_BRACK | L_PAREN => depth += 1,
                R_BRACK | R_PAREN => depth = depth.saturating_sub(1),
                _ => {}
            }
            n += 1;
            if depth == 0 {
                break;
            }
        }
    }
    while matches!(p.nth(n), PUBLIC_KW | PROTECTED_KW | PRIVATE_KW | ABSTRACT_KW) {
        n += 1;
    }
    match p.nth(n) {
        CLASS_KW => DeclKind::Class,
        INTERFACE_KW => DeclKind::Interface,
        ENUM_KW => DeclKind::Enum,
        ATTRIBUTE_KW => DeclKind::AttributeDef,
        IDENT
            if [SOURCE_KW, FILTER_KW, SINK_KW].iter().any(|&kw| p.nth_at_contextual(n, kw))
                && p.nth(n + 1) == IDENT
                && matches!(p.nth(n + 2), L_CURLY | L_ANGLE | EXTENDS_KW | IMPLEMENTS_KW) =>
        {
            DeclKind::Class
        }
        _ => DeclKind::Other,
    }
}

/// Tokens after which a class-diagram item can start again.
const ITEM_RECOVERY: TokenSet = TokenSet::new(&[
    PUBLIC_KW,
    PROTECTED_KW,
    PRIVATE_KW,
    ABSTRACT_KW,
    CLASS_KW,
    INTERFACE_KW,
    ENUM_KW,
    ATTRIBUTE_KW,
    IMPORT_KW,
    L_BRACK,
    R_CURLY,
]);

fn class_diagram_item(p: &mut Parser) {
    if p.at(IMPORT_KW) {
        import(p);
        return;
    }
    if diagram(p) {
        return;
    }
    match decl_kind(p) {
        DeclKind::Class => nested(p, class),
        DeclKind::Interface => nested(p, interface),
        DeclKind::Enum => enumeration(p),
        DeclKind::AttributeDef => nested(p, attribute_def),
        DeclKind::Other if p.at(L_BRACK) || p.at_ts(VISIBILITY) => {
            // Attributes or visibility before something that is not a declaration.
            let m = p.start();
            if p.at(L_BRACK) {
                attribute_list(p);
            }
            modifiers(p);
            p.err_expected_keyword(
                "expected `class`, `interface`, `enum`, `attribute`, `source`, `filter` or `sink`",
                &["class", "interface", "enum", "attribute", "source", "filter", "sink"],
                &|p| p.at_ts(ITEM_RECOVERY) || at_diagram_start(p),
            );
            m.complete(p, ERROR);
        }
        DeclKind::Other => p.err_recover_until("expected a class, interface, enum or attribute declaration", &|p| {
            p.at_ts(ITEM_RECOVERY) || at_diagram_start(p)
        }),
    }
}

/// Consumes the declaration keyword the lookahead saw, or reports what is there instead (the
/// lookahead and the attribute-list parser can disagree on broken attribute lists).
fn expect_decl_keyword(p: &mut Parser, keyword: SyntaxKind) -> bool {
    if p.at(keyword) {
        p.bump(keyword);
        true
    } else {
        p.err_recover_until(&format!("expected {}", keyword.describe()), &|p| p.at_ts(ITEM_RECOVERY));
        false
    }
}

/// Attribute list and modifiers that open a declaration.
fn decl_prefix(p: &mut Parser) {
    if p.at(L_BRACK) {
        attribute_list(p);
    }
    modifiers(p);
}

/// `abstract class Name<T> extends Base implements I, J { members }` (also `source`, `filter`,
/// `sink` component classes).
fn class(p: &mut Parser) {
    let m = p.start();
    decl_prefix(p);
    let keyword = match p.current_contextual() {
        Some(kind @ (SOURCE_KW | FILTER_KW | SINK_KW)) => kind,
        _ => CLASS_KW,
    };
    if !expect_decl_keyword(p, keyword) {
        m.complete(p, CLASS);
        return;
    }
    let what = describe_named(p, "class");
    name(p, "a class name");
    if p.at(L_ANGLE) {
        types::template_params(p);
    }
    if p.at(EXTENDS_KW) {
        let clause = p.start();
        p.bump(EXTENDS_KW);
        type_list(p, "a base class after `extends`");
        clause.complete(p, EXTENDS_CLAUSE);
    }
    if p.at(IMPLEMENTS_KW) {
        let clause = p.start();
        p.bump(IMPLEMENTS_KW);
        type_list(p, "an interface after `implements`");
        clause.complete(p, IMPLEMENTS_CLAUSE);
    }
    member_list(p, what);
    m.complete(p, CLASS);
}

/// `interface provider Name extends I { methods }`
fn interface(p: &mut Parser) {
    let m = p.start();
    decl_prefix(p);
    if !expect_decl_keyword(p, INTERFACE_KW) {
        m.complete(p, INTERFACE);
        return;
    }
    if (p.at_contextual(PROVIDER_KW) || p.at_contextual(PROCESSOR_KW)) && p.nth(1) == IDENT {
        let kind = p.current_contextual().unwrap_or(IDENT);
        p.bump(kind);
    }
    let what = describe_named(p, "interface");
    name(p, "an interface name");
    if p.at(L_ANGLE) {
        types::template_params(p);
    }
    if p.at(EXTENDS_KW) {
        let clause = p.start();
        p.bump(EXTENDS_KW);
        type_list(p, "an interface after `extends`");
        clause.complete(p, EXTENDS_CLAUSE);
    }
    member_list(p, what);
    m.complete(p, INTERFACE);
}

/// `attribute Name { fields }`
fn attribute_def(p: &mut Parser) {
    let m = p.start();
    decl_prefix(p);
    if !expect_decl_keyword(p, ATTRIBUTE_KW) {
        m.complete(p, ATTRIBUTE_DEF);
        return;
    }
    let what = describe_named(p, "attribute");
    name(p, "an attribute name");
    member_list(p, what);
    m.complete(p, ATTRIBUTE_DEF);
}

fn type_list(p: &mut Parser, what: &str) {
    if !types::at_type_start(p) {
        p.error_missing(format!("expected {what}"));
        return;
    }
    types::type_ref(p);
    while p.eat(COMMA) {
        types::type_ref(p);
    }
}

/// `enum Name { A, B = 2, [Attr] C }`
fn enumeration(p: &mut Parser) {
    let m = p.start();
    decl_prefix(p);
    if !expect_decl_keyword(p, ENUM_KW) {
        m.complete(p, ENUM);
        return;
    }
    let what = describe_named(p, "enum");
    name(p, "an enum name");
    if open_curly(p, format_args!("the values of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if p.at_name() || p.at(L_BRACK) {
                let value = p.start();
                if p.at(L_BRACK) {
                    attribute_list(p);
                }
                name(p, "an enum value name");
                if p.eat(EQ) {
                    expressions::expr_or_error(p);
                }
                value.complete(p, ENUM_VALUE);
            } else if at_decl_start(p) {
                break;
            } else {
                p.err_recover("expected an enum value name", TokenSet::new(&[COMMA, R_CURLY]));
            }
            if !p.at(R_CURLY) && !p.expect_with(COMMA, "between enum values") && !p.at_name() {
                if at_decl_start(p) {
                    break;
                }
                p.err_recover("expected `,` or `}`", TokenSet::new(&[COMMA, R_CURLY]));
                p.eat(COMMA);
            }
        }
        close_curly(p, what);
    }
    m.complete(p, ENUM);
}

/// Whether a new class-diagram declaration (or diagram) starts here: a sign that the current
/// body is missing its `}`.
fn at_decl_start(p: &Parser) -> bool {
    decl_kind(p) != DeclKind::Other || at_diagram_start(p) || p.at(IMPORT_KW)
}

/// `{ fields, methods, associations }` of a class, interface or attribute.
fn member_list(p: &mut Parser, what: Described) {
    let m = p.start();
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_decl_start(p) {
                break;
            }
            member(p);
        }
        close_curly(p, what);
    }
    m.complete(p, MEMBER_LIST);
}

/// Tokens at which a broken member ends.
const MEMBER_RECOVERY: TokenSet = TokenSet::new(&[PUBLIC_KW, PROTECTED_KW, PRIVATE_KW, L_BRACK, R_CURLY, CONST_KW]);

/// A field, method or association.
fn member(p: &mut Parser) {
    let at_member =
        p.at(L_BRACK) || p.at_ts(VISIBILITY) || at_qualifier(p) || types::at_type_start(p) || p.at_contextual(SELF_KW);
    if !at_member {
        p.err_recover("expected a field, method or association", MEMBER_RECOVERY);
        return;
    }
    let m = p.start();
    decl_prefix(p);
    if p.at_contextual(SELF_KW) {
        association(p);
        m.complete(p, ASSOCIATION);
        return;
    }
    if !types::type_ref(p) {
        // Only attributes/modifiers (`type_ref` reported it); a `;` still ends the member.
        p.eat(SEMICOLON);
        m.complete(p, FIELD);
        return;
    }
    name(p, "a member name");
    if p.at(L_PAREN) {
        types::param_list(p);
        if p.at(L_CURLY) {
            statements::block(p);
        } else if !p.eat(SEMICOLON) {
            if statements::at_statement_start(p) && !at_decl_start(p) {
                p.error_missing("expected `{` to open the method body");
                statements::block_without_open(p);
            } else {
                p.error_missing("expected `;` after the method declaration (or a `{` body)");
            }
        }
        m.complete(p, METHOD);
    } else {
        if p.eat(EQ) {
            expressions::expr_or_error(p);
        }
        p.expect_with(SEMICOLON, "after the field");
        m.complete(p, FIELD);
    }
}

/// `self aggregation [0 .. *] subImages : Image [1];`, after the modifiers.
fn association(p: &mut Parser) {
    p.bump(SELF_KW);
    if p.at_contextual(AGGREGATION_KW) || p.at_contextual(COMPOSITION_KW) {
        let kind = p.current_contextual().unwrap_or(IDENT);
        p.bump(kind);
    }
    if p.at(L_BRACK) {
        multiplicity(p);
    }
    name(p, "a role name for the association");
    if p.expect_with(COLON, "between the role name and the associated type") {
        types::type_ref(p);
    }
    if p.at(L_BRACK) {
        multiplicity(p);
    }
    p.expect_with(SEMICOLON, "after the association");
}

/// `[0 .. *]`, `[1]`
fn multiplicity(p: &mut Parser) {
    let m = p.start();
    p.bump(L_BRACK);
    let bound = |p: &mut Parser| {
        if p.at(INT_NUMBER) || p.at(STAR) {
            p.bump_any();
        } else {
            p.error_missing("expected a multiplicity bound (a number or `*`)");
        }
    };
    bound(p);
    if p.eat(DOT2) {
        bound(p);
    }
    if !p.eat(R_BRACK) {
        p.error_unclosed("expected `]` to close the multiplicity");
    }
    m.complete(p, MULTIPLICITY);
}
