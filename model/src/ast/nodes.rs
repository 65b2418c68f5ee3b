//! The typed node wrappers and their accessors, grouped by diagram kind.

use super::{ast_enum, ast_node, child, children, token, AstNode};
use crate::syntax::{SyntaxKind, SyntaxNode, SyntaxToken};

ast_node!(
    /// The root of a document.
    SourceFile, SOURCE_FILE
);

impl SourceFile {
    pub fn diagrams(&self) -> impl Iterator<Item = Diagram> {
        children(&self.syntax)
    }
}

ast_node!(ClassDiagram, CLASS_DIAGRAM);
ast_node!(ActivityDiagram, ACTIVITY_DIAGRAM);
ast_node!(ComponentDiagram, COMPONENT_DIAGRAM);
ast_node!(ComponentInstanceDiagram, COMPONENT_INSTANCE_DIAGRAM);
ast_enum!(
    /// A diagram of any kind.
    Diagram { ClassDiagram, ActivityDiagram, ComponentDiagram, ComponentInstanceDiagram }
);
