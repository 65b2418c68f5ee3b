//! Types, template parameters and parameter lists.

use super::*;

/// Built-in type keywords.
pub(super) const BUILTIN_TYPES: TokenSet = TokenSet::new(&[
    BOOL_KW, BYTE_KW, CHAR_KW, DOUBLE_KW, FLOAT_KW, INT_KW, LONG_KW, REAL_KW, SHORT_KW, STRING_KW, VOID_KW,
]);

/// Tokens a type can start with.
pub(super) const TYPE_START: TokenSet = BUILTIN_TYPES.union(TokenSet::new(&[UNSIGNED_KW, REF_KW, IDENT]));

pub(super) fn nth_at_type_keyword(p: &Parser, n: usize) -> bool {
    let kind = p.nth(n);
    BUILTIN_TYPES.contains(kind) || matches!(kind, UNSIGNED_KW | REF_KW | CONST_KW)
}

pub(super) fn at_type_start(p: &Parser) -> bool {
    p.at_ts(TYPE_START)
}

/// `ref unsigned Name<T>[]`: a type, with array suffixes.
pub(super) fn type_ref(p: &mut Parser) -> bool {
    type_ref_inner(p, true)
}

/// A type without array suffixes (for `new T[n]`).
pub(super) fn type_ref_no_array(p: &mut Parser) -> bool {
    type_ref_inner(p, false)
}

fn type_ref_inner(p: &mut Parser, arrays: bool) -> bool {
    if !at_type_start(p) {
        p.error_missing("expected a type");
        return false;
    }
    if !p.enter() {
        return false;
    }
    let m = p.start();
    p.eat(REF_KW);
    let unsigned = p.eat(UNSIGNED_KW);
    if p.at_ts(BUILTIN_TYPES) {
        p.bump_any();
    } else if p.at_name() {
        super::path(p);
        if p.at(L_ANGLE) {
            type_args(p);
        }
    } else if !unsigned {
        // `unsigned` alone means `unsigned int`, as in C.
        p.error_missing("expected a type name");
    }
    while arrays && p.at(L_BRACK) && p.nth(1) == R_BRACK {
        p.bump(L_BRACK);
        p.bump(R_BRACK);
    }
    m.complete(p, TYPE_REF);
    p.leave();
    true
}

/// `<T, unsigned byte>`
fn type_args(p: &mut Parser) {
    let m = p.start();
    p.bump(L_ANGLE);
    while !p.at(EOF) && !p.at(R_ANGLE) {
        if at_type_start(p) {
            type_ref(p);
        } else {
            p.err_recover("expected a type argument", TokenSet::new(&[COMMA, R_ANGLE, SEMICOLON, L_CURLY]));
            if !p.at(COMMA) {
                break;
            }
        }
        if !p.at(R_ANGLE) && !p.expect_with(COMMA, "between type arguments") && !at_type_start(p) {
            break;
        }
    }
    if !p.eat(R_ANGLE) {
        p.error_unclosed("expected `>` to close the type arguments");
    }
    m.complete(p, TYPE_ARGS);
}

/// `<T, U>` after a class or interface name.
pub(super) fn template_params(p: &mut Parser) {
    let m = p.start();
    p.bump(L_ANGLE);
    while !p.at(EOF) && !p.at(R_ANGLE) {
        if p.at_name() {
            let param = p.start();
            name(p, "a template parameter name");
            param.complete(p, TEMPLATE_PARAM);
        } else {
            p.err_recover("expected a template parameter name", TokenSet::new(&[COMMA, R_ANGLE, L_CURLY]));
            if !p.at(COMMA) {
                break;
            }
        }
        if !p.at(R_ANGLE) && !p.expect_with(COMMA, "between template parameters") && !p.at_name() {
            break;
        }
    }
    if !p.eat(R_ANGLE) {
        p.error_unclosed("expected `>` to close the template parameters");
    }
    m.complete(p, TEMPLATE_PARAMS);
}

/// `(const int a, out ref Image b)`
pub(super) fn param_list(p: &mut Parser) {
    let m = p.start();
    p.bump(L_PAREN);
    while !p.at(EOF) && !p.at(R_PAREN) {
        if at_type_start(p) || at_qualifier(p) || p.at(CONST_KW) {
            param(p);
        } else {
            p.err_recover("expected a parameter (`type name`)", TokenSet::new(&[COMMA, R_PAREN, L_CURLY, SEMICOLON]));
            if !p.at(COMMA) {
                break;
            }
        }
        if !p.eat(COMMA) && !p.at(R_PAREN) {
            if !at_type_start(p) {
                break;
            }
            p.error_missing("expected `,` between parameters");
        }
    }
    if !p.eat(R_PAREN) {
        p.error_unclosed("expected `)` to close the parameter list");
    }
    m.complete(p, PARAM_LIST);
}

fn param(p: &mut Parser) {
    let m = p.start();
    modifiers(p);
    type_ref(p);
    name(p, "a parameter name");
    m.complete(p, PARAM);
}
