//! Component diagrams (components, ports, connections) and component-instance diagrams
//! (instances, port instances, bindings).

use super::*;

/// `ComponentDiagram Name { components, nested component diagrams }`
pub(super) fn component_diagram(p: &mut Parser) {
    let m = p.start();
    let what = diagram_header(p, COMPONENT_DIAGRAM_KW, "component diagram");
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if p.at(IMPORT_KW) {
                import(p);
            } else if diagram(p) {
            } else if at_component(p) {
                nested(p, component);
            } else {
                p.err_recover_until(
                    "expected a component (`source`, `filter`, `sink` or `class` and the class name)",
                    &|p| at_component(p) || at_diagram_start(p) || p.at(IMPORT_KW),
                );
            }
        }
        close_curly(p, what);
    }
    m.complete(p, COMPONENT_DIAGRAM);
}

fn at_component(p: &Parser) -> bool {
    (p.at(CLASS_KW) || p.at_contextual(SOURCE_KW) || p.at_contextual(FILTER_KW) || p.at_contextual(SINK_KW))
        && p.nth_is_name(1)
}

fn at_port(p: &Parser) -> bool {
    (p.at_contextual(PORT_KW) && p.nth_is_name(1))
        || (p.at_contextual(ASYNC_KW) && (p.nth_at_contextual(1, PORT_KW) || p.nth_at_contextual(1, BUFFERED_KW)))
}

/// `source A.Camera { ports, connections, nested components }`
fn component(p: &mut Parser) {
    let m = p.start();
    let keyword = p.current_contextual().unwrap_or(CLASS_KW);
    p.bump(keyword);
    let what = describe_named(p, "component");
    path(p);
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_component(p) {
                nested(p, component);
            } else if at_port(p) {
                port(p);
            } else if p.at(L_BRACK) {
                connection(p, CONNECTION);
            } else if at_diagram_start(p) {
                break;
            } else {
                p.err_recover_until("expected a port, a connection `[…]` or a nested component", &|p| {
                    at_component(p) || at_port(p) || p.at(L_BRACK) || at_diagram_start(p)
                });
            }
        }
        close_curly(p, what);
    }
    m.complete(p, COMPONENT);
}

/// `async buffered port Name ( provider a : I, processor b : J );`
fn port(p: &mut Parser) {
    let m = p.start();
    if p.at_contextual(ASYNC_KW) {
        p.bump(ASYNC_KW);
        if p.at_contextual(BUFFERED_KW) {
            p.bump(BUFFERED_KW);
        }
    }
    if !p.at_contextual(PORT_KW) {
        p.error_missing("expected `port` after `async`/`buffered`");
        m.complete(p, PORT);
        return;
    }
    p.bump(PORT_KW);
    name(p, "a port name");
    if p.expect_with(L_PAREN, "with the port's connectors") {
        while !p.at(EOF) && !p.at(R_PAREN) {
            if p.at_contextual(PROVIDER_KW) || p.at_contextual(PROCESSOR_KW) {
                let c = p.start();
                let kind = p.current_contextual().unwrap_or(IDENT);
                p.bump(kind);
                name(p, "a connector name");
                // A missing `:` before a name is reported once and the name still parsed.
                if p.expect_with(COLON, "between the connector name and its interface") || p.at_name() {
                    path_or_error(p, "the connector's interface");
                }
                c.complete(p, CONNECTOR);
            } else {
                p.err_recover(
                    "expected a connector (`provider name : Interface` or `processor name : Interface`)",
                    TokenSet::new(&[COMMA, R_PAREN, SEMICOLON, R_CURLY]),
                );
                if !p.at(COMMA) {
                    break;
                }
            }
            if !p.at(R_PAREN) && !p.expect_with(COMMA, "between connectors") {
                break;
            }
        }
        if !p.eat(R_PAREN) {
            p.error_unclosed("expected `)` to close the port's connectors");
        }
    }
    p.eat(SEMICOLON);
    m.complete(p, PORT);
}

/// `[Name source a.b ==> target c.d]` (a connection, `CONNECTION`) or the same without a name
/// in an instance diagram (a binding, `BINDING`).
fn connection(p: &mut Parser, kind: SyntaxKind) {
    let m = p.start();
    p.bump(L_BRACK);
    // `[source …]` has no name unless it is itself called `source` (`[source source …]`).
    let named = p.at_name() && (!p.at_contextual(SOURCE_KW) || p.nth_at_contextual(1, SOURCE_KW));
    if named {
        name(p, "a connection name");
    }
    if p.at_contextual(SOURCE_KW) {
        p.bump(SOURCE_KW);
    } else {
        p.error_missing("expected `source`");
    }
    path_or_error(p, "the source connector (`port.connector`)");
    if p.expect_with(LONG_FAT_ARROW, "between source and target") {
        if p.at_contextual(TARGET_KW) {
            p.bump(TARGET_KW);
        } else {
            p.error_missing("expected `target` after `==>`");
        }
        path_or_error(p, "the target connector (`port.connector`)");
    }
    if !p.eat(R_BRACK) {
        if !p.at(R_CURLY) && !p.at(EOF) && !p.at(L_BRACK) && !p.at_name() {
            p.err_recover("expected `]`", TokenSet::new(&[R_BRACK, R_CURLY, L_BRACK]));
        }
        if !p.eat(R_BRACK) {
            p.error_unclosed("expected `]` to close the connection");
        }
    }
    p.eat(SEMICOLON);
    m.complete(p, kind);
}

/// `ComponentInstanceDiagram Name { instances, port instances, bindings }`
pub(super) fn component_instance_diagram(p: &mut Parser) {
    let m = p.start();
    let what = diagram_header(p, COMPONENT_INSTANCE_DIAGRAM_KW, "component-instance diagram");
    if open_curly(p, format_args!("the body of {what}")) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if p.at(IMPORT_KW) {
                import(p);
            } else if at_instance(p) {
                nested(p, instance);
            } else if at_port_instance(p) || p.at(L_BRACK) {
                // Before any instance, a port instance or binding belongs to none.
                p.error_here(
                    "a port instance or binding belongs to an instance: write it after `Name instantiates Type (…)`",
                );
                instance_member(p);
            } else {
                if at_diagram_start(p) {
                    break;
                }
                p.err_recover_until(
                    "expected an instance (`Name instantiates Type (…)`), a port instance or a binding",
                    &|p| at_instance(p) || at_port_instance(p) || p.at(L_BRACK) || at_diagram_start(p),
                );
            }
        }
        close_curly(p, what);
    }
    m.complete(p, COMPONENT_INSTANCE_DIAGRAM);
}

fn at_instance(p: &Parser) -> bool {
    p.at_name() && p.nth_at_contextual(1, INSTANTIATES_KW)
}

fn at_port_instance(p: &Parser) -> bool {
    p.at_name() && p.nth(1) == COLON
}

/// A port instance or binding, if one starts here.
fn instance_member(p: &mut Parser) -> bool {
    if at_port_instance(p) {
        port_instance(p);
    } else if p.at(L_BRACK) {
        connection(p, BINDING);
    } else {
        return false;
    }
    true
}

/// `Camera1 instantiates A.Camera (width = 640) { port instances, bindings }`, or the same
/// without the braces (Listing 28).
fn instance(p: &mut Parser) {
    let m = p.start();
    let what = describe_named(p, "instance");
    name(p, "an instance name");
    p.bump(INSTANTIATES_KW);
    path_or_error(p, "the component type after `instantiates`");
    if p.at(L_PAREN) {
        named_arg_list(p);
    }
    if p.eat(L_CURLY) {
        while !p.at(EOF) && !p.at(R_CURLY) {
            if at_instance(p) || at_diagram_start(p) {
                break;
            }
            if !instance_member(p) {
                p.err_recover_until(
                    "expected a port instance (`Name : Port ( … );`) or a binding `[ source … ==> target … ]`",
                    &|p| at_port_instance(p) || p.at(L_BRACK) || at_instance(p),
                );
            }
        }
        close_curly(p, what);
    } else {
        p.eat(SEMICOLON);
        // Listing 28's flat form: the instance's port instances and bindings follow it without
        // braces, up to the next instance; the tree is the braced form's, less the braces.
        while instance_member(p) {}
    }
    m.complete(p, COMPONENT_INSTANCE);
}

/// `Camera1ProviderPort : CameraImageProviderPort ( provider P = IImageProvider() );`
fn port_instance(p: &mut Parser) {
    let m = p.start();
    name(p, "a port instance name");
    p.bump(COLON);
    if p.at_name() {
        name_ref(p);
    } else {
        p.error_missing("expected the port's name after `:`");
    }
    if p.expect_with(L_PAREN, "with the port instance's connectors") {
        while !p.at(EOF) && !p.at(R_PAREN) {
            if p.at_contextual(PROVIDER_KW) || p.at_contextual(PROCESSOR_KW) {
                let c = p.start();
                let kind = p.current_contextual().unwrap_or(IDENT);
                p.bump(kind);
                name(p, "a connector name");
                if p.expect_with(EQ, "between the connector name and its interface") || p.at_name() {
                    path_or_error(p, "the connector's interface");
                    if p.at(L_PAREN) {
                        named_arg_list(p);
                    } else {
                        p.error_missing("expected `(` with the connector's field values");
                    }
                }
                c.complete(p, CID_CONNECTOR);
            } else {
                p.err_recover(
                    "expected a connector (`provider name = Interface()`)",
                    TokenSet::new(&[COMMA, SEMICOLON, R_PAREN, R_CURLY]),
                );
                if !p.at(COMMA) && !p.at(SEMICOLON) {
                    break;
                }
            }
            // Listing 24 ends each connector with `;` (and separates them with `,`); Listing 28
            // separates them with `,` only. `;`, `,` and `; ,` are all accepted.
            let semicolon = p.eat(SEMICOLON);
            if !p.eat(COMMA) && !semicolon {
                break;
            }
        }
        if !p.eat(R_PAREN) {
            p.error_unclosed("expected `)` to close the port instance's connectors");
        }
    }
    p.expect_with(SEMICOLON, "after the port instance");
    m.complete(p, PORT_INSTANCE);
}
