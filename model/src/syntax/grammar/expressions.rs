//! Expressions: a precedence-climbing parser with C's operator precedence.

use super::*;

/// Tokens an expression can start with.
const EXPR_START: TokenSet = TokenSet::new(&[
    INT_NUMBER,
    FLOAT_NUMBER,
    STRING,
    CHAR,
    TRUE_KW,
    FALSE_KW,
    NULL_KW,
    THIS_KW,
    IDENT,
    L_PAREN,
    NEW_KW,
    CALL_KW,
    MINUS,
    PLUS,
    BANG,
    TILDE,
    PLUS2,
    MINUS2,
    REF_KW,
]);

pub(super) fn at_expr_start(p: &Parser) -> bool {
    p.at_ts(EXPR_START)
}

/// Where a missing expression is reported without consuming anything.
const EXPR_RECOVERY: TokenSet =
    TokenSet::new(&[SEMICOLON, COMMA, R_PAREN, R_BRACK, R_CURLY, L_CURLY, COLON, FAT_ARROW, EOF]);

/// An expression, which the caller knows starts here.
pub(super) fn expr(p: &mut Parser) -> Option<CompletedMarker> {
    expr_bp(p, 1)
}

/// An expression, or an error where one is missing. Returns whether one was parsed.
pub(super) fn expr_or_error(p: &mut Parser) -> bool {
    if at_expr_start(p) {
        expr(p).is_some()
    } else if p.at_ts(EXPR_RECOVERY) {
        p.error_missing("expected an expression");
        false
    } else {
        p.err_and_bump("expected an expression");
        false
    }
}

/// Binding power of the binary operator at the current position (higher binds tighter),
/// its token kind, and whether it is right-associative.
fn binary_op(p: &Parser) -> Option<(u8, SyntaxKind, bool)> {
    // Composite `>` operators first: `>>=`, `>>`, `>=`.
    if p.at(R_ANGLE) {
        return Some(if p.at(SHREQ) {
            (1, SHREQ, true)
        } else if p.at(SHR) {
            (10, SHR, false)
        } else if p.at(GTEQ) {
            (9, GTEQ, false)
        } else {
            (9, R_ANGLE, false)
        });
    }
    let kind = p.current();
    let bp = match kind {
        EQ | PLUSEQ | MINUSEQ | STAREQ | SLASHEQ | PERCENTEQ | AMPEQ | PIPEEQ | CARETEQ | SHLEQ => {
            return Some((1, kind, true))
        }
        QUESTION => return Some((2, kind, true)),
        PIPE2 => 3,
        AMP2 => 4,
        PIPE => 5,
        CARET => 6,
        AMP => 7,
        EQ2 | NEQ => 8,
        L_ANGLE | LTEQ | AS_KW => 9,
        SHL => 10,
        PLUS | MINUS => 11,
        STAR | SLASH | PERCENT => 12,
        _ => return None,
    };
    Some((bp, kind, false))
}

/// Binding power of prefix operators' operands.
const PREFIX_BP: u8 = 13;

fn expr_bp(p: &mut Parser, min_bp: u8) -> Option<CompletedMarker> {
    // Too deep: keep the rest of this expression, not of the enclosing block, unanalysed.
    if p.chain_too_deep(1) {
        p.skip_deep_chain();
        return None;
    }
    if !p.enter() {
        return None;
    }
    let result = expr_bp_inner(p, min_bp);
    p.leave();
    result
}

fn expr_bp_inner(p: &mut Parser, min_bp: u8) -> Option<CompletedMarker> {
    let mut lhs = unary(p)?;
    let mut links = 0;
    while let Some((bp, op, right_assoc)) = binary_op(p) {
        if bp < min_bp {
            break;
        }
        links += 1;
        if p.chain_too_deep(links) {
            p.skip_deep_chain();
            break;
        }
        let m = lhs.precede(p);
        p.bump(op);
        let kind = match op {
            AS_KW => {
                types::type_ref(p);
                AS_EXPR
            }
            QUESTION => {
                expr_or_error(p);
                if p.expect_with(COLON, "in the conditional expression `c ? a : b`") {
                    operand(p, bp);
                }
                TERNARY_EXPR
            }
            _ => {
                operand(p, if right_assoc { bp } else { bp + 1 });
                BIN_EXPR
            }
        };
        lhs = m.complete(p, kind);
    }
    Some(lhs)
}

/// The right operand of a binary operator, or an error if it is missing.
fn operand(p: &mut Parser, min_bp: u8) {
    if at_expr_start(p) {
        expr_bp(p, min_bp);
    } else {
        expr_or_error(p);
    }
}

/// Prefix operators, C casts, then a postfix expression.
fn unary(p: &mut Parser) -> Option<CompletedMarker> {
    match p.current() {
        MINUS | PLUS | BANG | TILDE | PLUS2 | MINUS2 | REF_KW => {
            let m = p.start();
            p.bump_any();
            operand(p, PREFIX_BP);
            Some(m.complete(p, PREFIX_EXPR))
        }
        L_PAREN if at_c_cast(p) => {
            let m = p.start();
            p.bump(L_PAREN);
            types::type_ref(p);
            p.expect_with(R_PAREN, "to close the cast");
            operand(p, PREFIX_BP);
            Some(m.complete(p, CAST_EXPR))
        }
        _ => {
            let atom = atom(p)?;
            Some(postfix(p, atom))
        }
    }
}

/// `(float)x`: a parenthesised built-in type.
fn at_c_cast(p: &Parser) -> bool {
    types::BUILTIN_TYPES.contains(p.nth(1)) || p.nth(1) == UNSIGNED_KW
}

/// Calls, indexing, member and scope access, postfix `++`/`--`.
fn postfix(p: &mut Parser, mut lhs: CompletedMarker) -> CompletedMarker {
    let mut links = 0;
    loop {
        links += 1;
        let kind = match p.current() {
            L_PAREN => CALL_EXPR,
            L_BRACK => INDEX_EXPR,
            DOT => MEMBER_EXPR,
            COLON2 => SCOPE_EXPR,
            PLUS2 | MINUS2 => POSTFIX_EXPR,
            _ => return lhs,
        };
        if p.chain_too_deep(links) {
            p.skip_deep_chain();
            return lhs;
        }
        let m = lhs.precede(p);
        match kind {
            CALL_EXPR => arg_list(p),
            INDEX_EXPR => {
                p.bump(L_BRACK);
                expr_or_error(p);
                if !p.eat(R_BRACK) {
                    p.error_unclosed("expected `]` to close the index");
                }
            }
            MEMBER_EXPR | SCOPE_EXPR => {
                p.bump_any();
                if p.at_name() {
                    name_ref(p);
                } else if kind == MEMBER_EXPR {
                    p.error_missing("expected a member name after `.`");
                } else {
                    p.error_missing("expected a name after `::`");
                }
            }
            _ => p.bump_any(),
        }
        lhs = m.complete(p, kind);
    }
}

/// `(a, b, c)`
pub(super) fn arg_list(p: &mut Parser) {
    let m = p.start();
    p.bump(L_PAREN);
    while !p.at(EOF) && !p.at(R_PAREN) {
        if !expr_or_error(p) && !p.at(COMMA) {
            break;
        }
        if !p.eat(COMMA) && !p.at(R_PAREN) {
            if !at_expr_start(p) {
                break;
            }
            p.error_missing("expected `,` between arguments");
        }
    }
    if !p.eat(R_PAREN) {
        p.error_unclosed("expected `)` to close the argument list");
    }
    m.complete(p, ARG_LIST);
}

fn atom(p: &mut Parser) -> Option<CompletedMarker> {
    let m = p.start();
    let kind = match p.current() {
        INT_NUMBER | FLOAT_NUMBER | STRING | CHAR | TRUE_KW | FALSE_KW | NULL_KW => {
            p.bump_any();
            LITERAL
        }
        THIS_KW => {
            p.bump(THIS_KW);
            THIS_EXPR
        }
        IDENT => {
            name_ref(p);
            NAME_EXPR
        }
        L_PAREN => {
            p.bump(L_PAREN);
            expr_or_error(p);
            if !p.eat(R_PAREN) {
                p.error_unclosed("expected `)` to close the parenthesis");
            }
            PAREN_EXPR
        }
        NEW_KW => {
            p.bump(NEW_KW);
            types::type_ref_no_array(p);
            if p.at(L_PAREN) {
                arg_list(p);
            } else if p.eat(L_BRACK) {
                expr_or_error(p);
                if !p.eat(R_BRACK) {
                    p.error_unclosed("expected `]` to close the array size");
                }
            } else {
                p.error_missing("expected `(` with constructor arguments or `[` with an array size after the type");
            }
            NEW_EXPR
        }
        CALL_KW => call(p),
        _ => {
            m.abandon(p);
            expr_or_error(p);
            return None;
        }
    };
    Some(m.complete(p, kind))
}

/// `call behavior X(…)`, `call interface I.m(…)`, `call Class::m(…)`, `call I.m(…)`.
fn call(p: &mut Parser) -> SyntaxKind {
    p.bump(CALL_KW);
    if p.at_contextual(BEHAVIOR_KW) && p.nth_is_name(1) {
        p.bump(BEHAVIOR_KW);
        path(p);
        if p.at(L_PAREN) {
            arg_list(p);
        }
        return CALL_BEHAVIOR_EXPR;
    }
    let explicit_interface = p.eat(INTERFACE_KW);
    if !path_or_error(p, "the behavior, `Class::method` or `Interface.method` to call") {
        return CALL_METHOD_EXPR;
    }
    let kind = if !explicit_interface && p.eat(COLON2) {
        if p.at_name() {
            name_ref(p);
        } else {
            p.error_missing("expected a method name after `::`");
        }
        CALL_METHOD_EXPR
    } else {
        CALL_INTERFACE_EXPR
    };
    if p.at(L_PAREN) {
        arg_list(p);
    } else {
        p.error_missing("expected `(` with the call's arguments");
    }
    kind
}
