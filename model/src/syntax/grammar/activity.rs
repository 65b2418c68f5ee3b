//! Activity diagrams: parameters, the variable section, swimlanes, nodes and transitions.

use super::*;
use crate::syntax::NodeKind;

/// `ActivityDiagram Name(params), owner A.B { variables, swimlanes, nodes }`
pub(super) fn activity_diagram(p: &mut Parser) {
    let m = p.start();
    let what = diagram_header(p, ACTIVITY_DIAGRAM_KW, "activity diagram");
    if p.at(L_PAREN) {
        types::param_list(p);
    }
    if p.at(COMMA) && p.nth_at_contextual(1, OWNER_KW) {
        owner_clause(p);
    }
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_diagram_start(p) {
                break;
            }
            activity_item(p);
        }
        close_curly(p, what);
    }
    m.complete(p, ACTIVITY_DIAGRAM);
}

/// `, owner A.B`
fn owner_clause(p: &mut Parser) {
    let m = p.start();
    p.bump(COMMA);
    p.bump(OWNER_KW);
    path_or_error(p, "the owner class after `owner`");
    m.complete(p, OWNER_CLAUSE);
}

/// The kind of node whose declaration (`action name`) starts here, if one does.
fn at_node(p: &Parser) -> Option<NodeKind> {
    let keyword = if p.at(LOOP_KW) { LOOP_KW } else { p.current_contextual()? };
    NodeKind::of_keyword(keyword).filter(|_| p.nth_is_name(1))
}

/// `strat S { … }`: a word, a name and a body or parameters — a node whose keyword is
/// misspelt (no variable is followed by `{` or `(`).
fn at_misspelt_node(p: &Parser) -> bool {
    p.at(IDENT) && p.nth_is_name(1) && matches!(p.nth(2), L_CURLY | L_PAREN)
}

/// Whether something that belongs to an activity diagram, not inside a node, starts here.
fn at_activity_level_start(p: &Parser) -> bool {
    at_node(p).is_some() || (p.at_contextual(SWIMLANE_KW) && p.nth_is_name(1)) || at_diagram_start(p)
}

const VARIABLE_START: TokenSet =
    types::TYPE_START.union(TokenSet::new(&[PUBLIC_KW, PROTECTED_KW, PRIVATE_KW, CONST_KW, L_BRACK]));

fn activity_item(p: &mut Parser) {
    if p.at(IMPORT_KW) {
        import(p);
    } else if p.at_contextual(SWIMLANE_KW) && p.nth_is_name(1) {
        nested(p, swimlane);
    } else if at_node(p).is_some() {
        nested(p, node);
    } else if p.at(VAR_KW) || (p.at(CONST_KW) && !p.nth_at(1, CONST_KW)) {
        statements::var_decl(p);
    } else if at_misspelt_node(p) {
        let keywords = NodeKind::ALL.map(NodeKind::keyword);
        p.err_expected_keyword("expected a node (`start`, `action`, `final`, …)", &keywords, &|p| {
            at_activity_level_start(p) || p.at(R_CURLY) || p.at(IMPORT_KW)
        });
    } else if p.at_ts(VARIABLE_START) || at_qualifier(p) {
        variable(p);
    } else {
        p.err_recover_until("expected a variable, `swimlane` or a node (`start`, `action`, `final`, …)", &|p| {
            at_activity_level_start(p) || p.at(R_CURLY) || p.at(IMPORT_KW)
        });
    }
}

/// A variable-section entry: `public int gidx;`, `[Attr] int2 coordinate = new int2(0, 0);`
fn variable(p: &mut Parser) {
    let m = p.start();
    if p.at(L_BRACK) {
        attribute_list(p);
    }
    modifiers(p);
    if types::type_ref(p) {
        name(p, "a variable name");
        if p.eat(EQ) {
            expressions::expr_or_error(p);
        }
        p.expect_with(SEMICOLON, "after the variable");
    }
    m.complete(p, VARIABLE);
}

/// `swimlane Name, owner A.B { nodes }`
fn swimlane(p: &mut Parser) {
    let m = p.start();
    p.bump(SWIMLANE_KW);
    let what = describe_named(p, "swimlane");
    name(p, "a swimlane name");
    if p.at(COMMA) && p.nth_at_contextual(1, OWNER_KW) {
        owner_clause(p);
    }
    if open_curly(p, format_args!("the nodes of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_node(p).is_some() {
                nested(p, node);
            } else if at_activity_level_start(p) {
                break;
            } else {
                p.err_recover_until("expected a node (`start`, `action`, `decision`, `calc`, `final`, …)", &|p| {
                    at_activity_level_start(p) || p.at(R_CURLY)
                });
            }
        }
        close_curly(p, what);
    }
    m.complete(p, SWIMLANE);
}

/// Any activity node.
fn node(p: &mut Parser) {
    let Some(node_kind) = at_node(p) else { return };
    let m = p.start();
    p.bump(node_kind.keyword_kind());
    let what = Described::current(p, "node");
    name(p, "a node name");
    let kind = node_kind.syntax_kind();
    match kind {
        LOOP_NODE | LOOP_WINDOW_NODE => {
            if p.at(L_PAREN) {
                loop_header(p);
            } else {
                p.error_missing(format!("expected `(` with the loop sections of {what}"));
            }
        }
        FINAL_NODE => {
            if p.eat(RETURN_KW) {
                expressions::expr_or_error(p);
            }
            if !p.eat(SEMICOLON) && p.at(L_CURLY) {
                node_body(p, what);
            }
            m.complete(p, kind);
            return;
        }
        _ => {
            if p.at(L_PAREN) {
                types::param_list(p);
            }
        }
    }
    node_body(p, what);
    m.complete(p, kind);
}

/// `(setup; test; increment)` of a loop or loopWindow node; a single section is a `while`.
fn loop_header(p: &mut Parser) {
    let m = p.start();
    p.bump(L_PAREN);
    loop {
        let section = p.start();
        while !p.at(EOF) && !p.at(SEMICOLON) && !p.at(R_PAREN) {
            if p.at(VAR_KW)
                || p.at(CONST_KW)
                || (p.at(REF_KW) && p.nth_is_name(1))
                || statements::at_declaration_without_var(p)
            {
                statements::var_decl_head(p);
            } else if !expressions::expr_or_error(p) {
                break;
            }
            if !p.eat(COMMA) {
                break;
            }
        }
        section.complete(p, LOOP_SECTION);
        if !p.eat(SEMICOLON) {
            break;
        }
    }
    if !p.eat(R_PAREN) {
        p.error_unclosed("expected `)` to close the loop sections");
    }
    m.complete(p, LOOP_HEADER);
}

/// `{ statements and transitions }`. Without `{`, transitions that follow are still parsed.
fn node_body(p: &mut Parser, what: Described) {
    let m = p.start();
    if p.eat(L_CURLY) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_transition(p) {
                transition(p);
            } else if at_node(p).is_some() && p.braces_balanced() {
                // A nested node: the node is a container (Sec. 9.2.2.3). With unbalanced
                // braces the keyword more likely begins the next node after a missing `}`.
                node(p);
            } else if at_activity_level_start(p) {
                break;
            } else {
                statements::statement(p);
            }
        }
        close_curly(p, format_args!("the body of {what}"));
    } else {
        // Parse what follows as the body all the same; its `}` is taken only when statements
        // show that a body was meant (`start S => init;` has no braces at all).
        p.error_missing(format!("expected `{{` to open the body of {what}"));
        let mut saw_statement = false;
        while !p.at(EOF) && !p.at(R_CURLY) && !at_activity_level_start(p) {
            if at_transition(p) {
                transition(p);
            } else if statements::at_statement_start(p) {
                statements::statement(p);
                saw_statement = true;
            } else {
                break;
            }
        }
        if saw_statement {
            p.eat(R_CURLY);
        }
    }
    m.complete(p, NODE_BODY);
}

fn at_transition(p: &Parser) -> bool {
    p.at(FAT_ARROW) || p.at(L_BRACK)
}

/// `[guard] => target(args);`
fn transition(p: &mut Parser) {
    let m = p.start();
    if p.at(L_BRACK) {
        let guard = p.start();
        p.bump(L_BRACK);
        if !p.at(R_BRACK) {
            expressions::expr_or_error(p);
        }
        if !p.eat(R_BRACK) {
            p.error_unclosed("expected `]` to close the guard");
        }
        guard.complete(p, GUARD);
    }
    if p.expect_with(FAT_ARROW, "after the guard") {
        if p.at_name() {
            name_ref(p);
            if p.at(L_PAREN) {
                expressions::arg_list(p);
            }
        } else {
            p.error_missing("expected the target node's name after `=>`");
        }
    }
    p.expect_with(SEMICOLON, "after the transition");
    m.complete(p, TRANSITION);
}
