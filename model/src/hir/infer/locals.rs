//! The names a body is given before its own statements: the diagram's parameters and
//! variables, and for an activity node the parameters and loop variables of the nodes that hold
//! it (Sec. 9.2.2.3) and its own.

use crate::ast::{self, AstNode, HasName};

/// The parameters and variables of an activity diagram: the locals every node body sees.
pub fn diagram_locals(diagram: &ast::ActivityDiagram) -> Vec<(String, Option<ast::TypeRef>)> {
    let mut locals: Vec<(String, Option<ast::TypeRef>)> =
        diagram.params().filter_map(|p| Some((p.name()?.text(), p.type_ref()))).collect();
    locals.extend(diagram.variables().filter_map(|v| Some((v.name()?.text(), v.type_ref()))));
    locals.extend(diagram.var_decls().filter_map(|v| Some((v.name()?.text(), v.type_ref()))));
    locals
}

/// Names declared by a loop header or a parameter list, for node bodies.
pub fn header_declarations(node: &ast::ActivityNode) -> Vec<(String, Option<ast::TypeRef>)> {
    // The nodes that hold this one first (their parameters and loop variables are in scope in
    // their bodies, nested nodes included), the innermost last, so that it shadows.
    let mut chain = vec![node.clone()];
    while let Some(container) = chain.last().and_then(ast::ActivityNode::container) {
        chain.push(container);
    }
    let mut out: Vec<(String, Option<ast::TypeRef>)> = Vec::new();
    for node in chain.iter().rev() {
        out.extend(node.params().filter_map(|p| Some((p.name()?.text(), p.type_ref()))));
        if let Some(header) = node.loop_header() {
            for decl in header.syntax().descendants().filter_map(ast::VarDecl::cast) {
                if let Some(name) = decl.name() {
                    out.push((name.text(), decl.type_ref()));
                }
            }
        }
    }
    out
}
