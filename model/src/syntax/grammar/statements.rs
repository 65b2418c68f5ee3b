//! Statements of the expression language: declarations, blocks, control flow.

use super::*;

/// `{ statements }`
pub(super) fn block(p: &mut Parser) {
    if !p.enter() {
        return;
    }
    let m = p.start();
    p.bump(L_CURLY);
    block_statements(p);
    m.complete(p, BLOCK);
    p.leave();
}

/// A block whose `{` is missing (reported by the caller): its statements up to the `}`.
pub(super) fn block_without_open(p: &mut Parser) {
    if !p.enter() {
        return;
    }
    let m = p.start();
    block_statements(p);
    m.complete(p, BLOCK);
    p.leave();
}

/// Whether a statement (not a declaration of the enclosing scope) starts here.
pub(super) fn at_statement_start(p: &Parser) -> bool {
    expressions::at_expr_start(p)
        || matches!(
            p.current(),
            VAR_KW | IF_KW | LOOP_KW | DO_KW | FOR_KW | SWITCH_KW | RETURN_KW | BREAK_KW | CONTINUE_KW
        )
}

fn block_statements(p: &mut Parser) {
    while !p.at(EOF) && !p.at(R_CURLY) {
        if at_block_end(p) {
            break;
        }
        statement(p);
    }
    close_curly(p, "the block");
}

/// Where a block must have ended: a diagram-level construct follows (a missing `}`).
fn at_block_end(p: &Parser) -> bool {
    at_diagram_start(p)
        || (p.at_contextual(SWIMLANE_KW) && p.nth_is_name(1))
        || matches!(p.current(), PUBLIC_KW | PROTECTED_KW | PRIVATE_KW)
        || (matches!(p.current(), CLASS_KW | INTERFACE_KW | ENUM_KW | ABSTRACT_KW) && at_type_header(p))
}

/// `class Name {`, `interface provider Name extends`, …: a declaration header, not a statement.
fn at_type_header(p: &Parser) -> bool {
    let mut n = 1;
    if p.nth_at(n, CLASS_KW) || p.nth_at_contextual(n, PROVIDER_KW) || p.nth_at_contextual(n, PROCESSOR_KW) {
        n += 1;
    }
    p.nth_is_name(n) && matches!(p.nth(n + 1), L_CURLY | L_ANGLE | EXTENDS_KW | IMPLEMENTS_KW)
}

/// Tokens that end a broken statement.
const STATEMENT_RECOVERY: TokenSet = TokenSet::new(&[
    SEMICOLON, R_CURLY, VAR_KW, IF_KW, FOR_KW, LOOP_KW, DO_KW, SWITCH_KW, RETURN_KW, FAT_ARROW, L_BRACK,
]);

/// One statement.
pub(super) fn statement(p: &mut Parser) {
    match p.current() {
        L_CURLY => {
            block(p);
            if p.at(SEMICOLON) {
                let m = p.start();
                p.bump(SEMICOLON);
                m.complete(p, EMPTY_STMT);
            }
        }
        SEMICOLON => {
            let m = p.start();
            p.bump(SEMICOLON);
            m.complete(p, EMPTY_STMT);
        }
        VAR_KW | CONST_KW => var_decl(p),
        REF_KW if p.nth_is_name(1) || types::nth_at_type_keyword(p, 1) => var_decl(p),
        IF_KW => nested(p, if_stmt),
        LOOP_KW if p.nth(1) == L_PAREN => nested(p, loop_stmt),
        DO_KW => nested(p, do_loop_stmt),
        FOR_KW => nested(p, for_stmt),
        SWITCH_KW => nested(p, switch_stmt),
        RETURN_KW => {
            let m = p.start();
            p.bump(RETURN_KW);
            if !p.at(SEMICOLON) && expressions::at_expr_start(p) {
                expressions::expr(p);
            }
            p.expect_with(SEMICOLON, "after `return`");
            m.complete(p, RETURN_STMT);
        }
        BREAK_KW | CONTINUE_KW => {
            let kind = if p.at(BREAK_KW) { BREAK_STMT } else { CONTINUE_STMT };
            let m = p.start();
            p.bump_any();
            p.expect_with(SEMICOLON, "after the statement");
            m.complete(p, kind);
        }
        IDENT if (p.at_contextual(LOOPWINDOW2D_KW) || p.at_contextual(LOOPWINDOW3D_KW)) && p.nth(1) == L_PAREN => {
            nested(p, loop_window_stmt)
        }
        _ if at_declaration_without_var(p) => {
            // `int i = 0;` as in C: one clear error, and the declaration is still understood.
            var_decl(p);
        }
        _ if expressions::at_expr_start(p) => {
            let m = p.start();
            expressions::expr(p);
            p.expect_with(SEMICOLON, "after the statement");
            m.complete(p, EXPR_STMT);
        }
        _ => p.err_recover("expected a statement", STATEMENT_RECOVERY),
    }
}

/// `int i`, `unsigned byte b`, `Image img =`: a C-style declaration missing its `var`.
pub(super) fn at_declaration_without_var(p: &Parser) -> bool {
    match p.current() {
        kind if types::BUILTIN_TYPES.contains(kind) => p.nth_is_name(1),
        UNSIGNED_KW => true,
        IDENT => p.nth_is_name(1) && matches!(p.nth(2), EQ | SEMICOLON | COMMA),
        _ => false,
    }
}

/// `var int i = 0;`, `const int j = 0;`, `var ref Image image;`
pub(super) fn var_decl(p: &mut Parser) {
    let m = p.start();
    var_decl_head_inner(p);
    p.expect_with(SEMICOLON, "after the variable declaration");
    m.complete(p, VAR_DECL);
}

/// A declaration without `;` (in loop headers): its own VAR_DECL node.
pub(super) fn var_decl_head(p: &mut Parser) {
    let m = p.start();
    var_decl_head_inner(p);
    m.complete(p, VAR_DECL);
}

fn var_decl_head_inner(p: &mut Parser) {
    if at_declaration_without_var(p) {
        p.error_here("local variables are declared with `var` (or `const`): `var int i = 0;`");
    }
    // `var`, `const`, `var ref`, `const ref` or `ref`; the `ref` goes into the type.
    if p.at(VAR_KW) || p.at(CONST_KW) {
        p.bump_any();
    }
    modifiers(p);
    if types::type_ref(p) {
        name(p, "a variable name");
        if p.eat(EQ) {
            expressions::expr_or_error(p);
        }
    }
}

fn paren_condition(p: &mut Parser, what: &str) {
    if p.expect_with(L_PAREN, what) {
        expressions::expr_or_error(p);
        if !p.eat(R_PAREN) {
            p.error_unclosed("expected `)` to close the condition");
        }
    }
}

/// A statement body that should be a block; anything else is parsed as one statement.
fn body(p: &mut Parser) {
    if p.at(L_CURLY) {
        block(p);
    } else {
        statement(p);
    }
}

/// `if (c) { … } else { … };`
fn if_stmt(p: &mut Parser) {
    let m = p.start();
    p.bump(IF_KW);
    paren_condition(p, "after `if`");
    body_no_semi(p);
    if p.at(ELSE_KW) {
        let e = p.start();
        p.bump(ELSE_KW);
        if p.at(IF_KW) {
            nested(p, if_stmt);
        } else {
            body_no_semi(p);
        }
        e.complete(p, ELSE_BRANCH);
    }
    p.eat(SEMICOLON);
    m.complete(p, IF_STMT);
}

/// The branch of an `if`: a block (its trailing `;` belongs to the `if`) or a statement.
fn body_no_semi(p: &mut Parser) {
    if p.at(L_CURLY) {
        block(p);
    } else if p.at(SEMICOLON) {
        // `if (c);` — allowed, empty.
    } else {
        statement(p);
    }
}

/// `loop (c) { … };`
fn loop_stmt(p: &mut Parser) {
    let m = p.start();
    p.bump(LOOP_KW);
    paren_condition(p, "after `loop`");
    body(p);
    p.eat(SEMICOLON);
    m.complete(p, LOOP_STMT);
}

/// `do { … } loop (c);`
fn do_loop_stmt(p: &mut Parser) {
    let m = p.start();
    p.bump(DO_KW);
    body(p);
    if p.expect_with(LOOP_KW, "after the body of `do`") {
        paren_condition(p, "after `loop`");
    }
    p.expect_with(SEMICOLON, "after `do … loop(…)`");
    m.complete(p, DO_LOOP_STMT);
}

/// `for (init : step : condition) { … }`
fn for_stmt(p: &mut Parser) {
    let m = p.start();
    p.bump(FOR_KW);
    if p.expect_with(L_PAREN, "after `for`") {
        let section = |p: &mut Parser| {
            if p.at(VAR_KW) || p.at(CONST_KW) {
                var_decl_head(p);
            } else {
                expressions::expr_or_error(p);
            }
        };
        section(p);
        if p.expect_with(COLON, "after the loop initialisation (`for(init : step : condition)`)") {
            section(p);
            if p.expect_with(COLON, "after the loop step (`for(init : step : condition)`)") {
                section(p);
            }
        }
        if !p.eat(R_PAREN) {
            p.error_unclosed("expected `)` to close the `for` header");
        }
    }
    body(p);
    p.eat(SEMICOLON);
    m.complete(p, FOR_STMT);
}

/// `switch i: { case 0: {} default: {} };`
fn switch_stmt(p: &mut Parser) {
    let m = p.start();
    p.bump(SWITCH_KW);
    expressions::expr_or_error(p);
    p.eat(COLON);
    if open_curly(p, "the cases of `switch`") {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if p.at(CASE_KW) || p.at(DEFAULT_KW) {
                let case = p.start();
                if p.eat(CASE_KW) {
                    expressions::expr_or_error(p);
                } else {
                    p.bump(DEFAULT_KW);
                }
                p.expect_with(COLON, "after the case label");
                while !p.at(EOF) && !p.at(R_CURLY) && !p.at(CASE_KW) && !p.at(DEFAULT_KW) {
                    if at_block_end(p) {
                        break;
                    }
                    statement(p);
                }
                case.complete(p, SWITCH_CASE);
            } else if at_block_end(p) {
                break;
            } else {
                p.err_recover("expected `case` or `default`", TokenSet::new(&[CASE_KW, DEFAULT_KW, R_CURLY]));
            }
        }
        close_curly(p, "the `switch`");
    }
    p.eat(SEMICOLON);
    m.complete(p, SWITCH_STMT);
}

/// `loopwindow2D(u = -r : r, v = -r : r) { … };`
fn loop_window_stmt(p: &mut Parser) {
    let m = p.start();
    let kind = p.current_contextual().unwrap_or(IDENT);
    p.bump(kind);
    p.bump(L_PAREN);
    while !p.at(EOF) && !p.at(R_PAREN) {
        let dim = p.start();
        if p.at(VAR_KW) || p.at(CONST_KW) {
            var_decl_head(p);
        } else {
            expressions::expr_or_error(p);
        }
        if p.expect_with(COLON, "between the start and the end of the window range") {
            expressions::expr_or_error(p);
        }
        dim.complete(p, LOOP_WINDOW_DIM);
        if !p.eat(COMMA) {
            break;
        }
    }
    if !p.eat(R_PAREN) {
        p.error_unclosed("expected `)` to close the window ranges");
    }
    body(p);
    p.eat(SEMICOLON);
    m.complete(p, LOOP_WINDOW_STMT);
}
