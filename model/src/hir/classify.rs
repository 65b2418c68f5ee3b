//! What a name written in the text refers to: a workspace definition (a segment of a qualified
//! name), a member of a type (`call C::m`, a field of the owner class), a node of the same
//! activity diagram (`=> target`), or a parameter or variable in scope. Editor features turn the
//! answer into places and text; they do not resolve names themselves.

use super::{definitions::Definition, scope::Scope, semantics::Semantics};
use crate::{
    ast::{self, AstNode, HasName},
    syntax::{SyntaxKind, SyntaxNode},
};

/// The meaning of a name reference.
#[derive(Debug, Clone)]
pub enum NameRefClass<'db> {
    /// A diagram or type of the workspace.
    Definition(&'db Definition),
    /// A field, association or method, with the type that declares it (maybe a base).
    Member { owner: &'db Definition, member: ast::Member },
    /// A node of the same activity diagram.
    Node(ast::ActivityNode),
    /// A parameter or variable: its declaration (`PARAM`, `VAR_DECL` or `VARIABLE`).
    Local(SyntaxNode),
}

impl<'db> Semantics<'db> {
    /// What `name_ref` means where it is written; `None` where it names nothing (or something
    /// only the component checks know, like `port.connector`).
    pub fn classify_name_ref(&self, name_ref: &ast::NameRef) -> Option<NameRefClass<'db>> {
        let parent = name_ref.syntax().parent()?;
        match parent.kind() {
            SyntaxKind::PATH => {
                let path = ast::Path::cast(parent)?;
                self.resolve_path_segment(&path, name_ref).map(NameRefClass::Definition)
            }
            SyntaxKind::TRANSITION => self.transition_target(name_ref).map(NameRefClass::Node),
            SyntaxKind::CALL_METHOD_EXPR => {
                let class = ast::CallMethodExpr::cast(parent)?.class()?;
                let def = self.resolve(&Scope::at(name_ref.syntax()), &class.text())?;
                self.member(def, &name_ref.text())
            }
            SyntaxKind::NAME_EXPR => self.name_in_body(name_ref),
            _ => None,
        }
    }

    /// The node `=> target` names, in the transition's activity diagram.
    pub fn transition_target(&self, target: &ast::NameRef) -> Option<ast::ActivityNode> {
        let wanted = target.text();
        let diagram = target.syntax().ancestors().find_map(ast::ActivityDiagram::cast)?;
        diagram
            .syntax()
            .descendants()
            .filter_map(ast::ActivityNode::cast)
            .find(|n| n.name().is_some_and(|name| name.text() == wanted))
    }

    /// A field, association or method `name` of type `def` or a base.
    pub fn member(&self, def: &'db Definition, name: &str) -> Option<NameRefClass<'db>> {
        let (owner, ()) = self.find_member(&def.fqn, &|ty| {
            (ty.fields.iter().any(|f| f.name == name) || ty.methods.iter().any(|m| m.name == name)).then_some(())
        })?;
        let member = self.member_declaration(owner, name)?;
        Some(NameRefClass::Member { owner, member })
    }

    /// A name in an expression: a local declaration, a parameter or variable of the enclosing
    /// body or diagram, a member of the owner class, or a type used as a scope
    /// (`HCImageChannelOrder.RGBA`).
    fn name_in_body(&self, name_ref: &ast::NameRef) -> Option<NameRefClass<'db>> {
        let name = name_ref.text();
        for ancestor in name_ref.syntax().ancestors() {
            if let Some(declaration) = locals_of(&ancestor).find(|d| declared_name(d).is_some_and(|n| n == name)) {
                return Some(NameRefClass::Local(declaration));
            }
        }
        // Members and types are looked up only in bodies that have an owner class.
        let owner = self.owner_at(name_ref.syntax())?;
        if let Some(found) = self.member(owner, &name) {
            return Some(found);
        }
        self.resolve(&Scope::at(name_ref.syntax()), &name).map(NameRefClass::Definition)
    }
}

/// The parameter and variable declarations that `node` puts in scope for what it contains.
fn locals_of(node: &SyntaxNode) -> Box<dyn Iterator<Item = SyntaxNode>> {
    match node.kind() {
        SyntaxKind::BLOCK | SyntaxKind::NODE_BODY | SyntaxKind::SWITCH_CASE => {
            Box::new(node.children().filter(|c| c.kind() == SyntaxKind::VAR_DECL))
        }
        SyntaxKind::METHOD
        | SyntaxKind::ACTION_NODE
        | SyntaxKind::CALC_NODE
        | SyntaxKind::CALC_RANGE_NODE
        | SyntaxKind::DECISION_NODE
        | SyntaxKind::LOOP_NODE
        | SyntaxKind::LOOP_WINDOW_NODE => Box::new(
            node.descendants()
                .filter(|c| c.kind() == SyntaxKind::PARAM || (c.kind() == SyntaxKind::VAR_DECL && in_loop_header(c))),
        ),
        SyntaxKind::ACTIVITY_DIAGRAM => Box::new(
            node.children()
                .filter(|c| matches!(c.kind(), SyntaxKind::VARIABLE | SyntaxKind::VAR_DECL))
                .chain(node.children().filter(|c| c.kind() == SyntaxKind::PARAM_LIST).flat_map(|l| l.children())),
        ),
        _ => Box::new(std::iter::empty()),
    }
}

fn declared_name(declaration: &SyntaxNode) -> Option<String> {
    declaration.children().find(|c| c.kind() == SyntaxKind::NAME).map(|n| n.text().to_string())
}

fn in_loop_header(node: &SyntaxNode) -> bool {
    node.ancestors().any(|a| a.kind() == SyntaxKind::LOOP_HEADER)
}
