//! Typed AST: thin, zero-copy wrappers over syntax nodes; every accessor returns `Option` or an
//! iterator, because half-typed documents are the normal case.
//!
//! The node types and their plain accessors are generated from `model/gudsl.ungram`
//! (`generated.rs`); accessors that need more than "the child of this kind" are written by hand
//! in `node_ext.rs`, what a literal denotes in `literal.rs`.

#[rustfmt::skip]
mod generated;
mod literal;
mod node_ext;
mod node_kind;
#[cfg(test)]
mod tests;
mod walk;

use std::marker::PhantomData;

pub use crate::syntax::NodeKind;
pub use generated::*;
pub use literal::LiteralValue;
pub use node_ext::*;
pub use walk::{own_descendants, owns_at_least, AndNested, OwnDescendants};

use crate::syntax::{Parse, SyntaxKind, SyntaxNode};

impl Parse {
    /// The typed root.
    pub fn source_file(&self) -> SourceFile {
        SourceFile { syntax: self.syntax_node() }
    }
}

/// A typed view of one kind of syntax node (or of several, for enums).
pub trait AstNode: Sized {
    fn can_cast(kind: SyntaxKind) -> bool;
    fn cast(node: SyntaxNode) -> Option<Self>;
    fn syntax(&self) -> &SyntaxNode;
}

/// The child nodes of one AST type, in order. It steps over the other children in the green
/// tree: only the children it yields get a syntax node of their own.
#[derive(Debug, Clone)]
pub struct AstChildren<N> {
    next: Option<SyntaxNode>,
    node: PhantomData<N>,
}

impl<N: AstNode> Iterator for AstChildren<N> {
    type Item = N;
    fn next(&mut self) -> Option<N> {
        let current = self.next.take()?;
        self.next = current.next_sibling_by_kind(&N::can_cast);
        N::cast(current)
    }
}

/// Items with a defining name.
pub trait HasName: AstNode {
    fn name(&self) -> Option<Name> {
        support::child(self.syntax())
    }
}

/// Items with attribute lists and modifiers in front.
pub trait HasModifiers: AstNode {
    fn modifiers(&self) -> Option<Modifiers> {
        support::child(self.syntax())
    }
    fn attribute_lists(&self) -> Vec<AttributeList> {
        support::children(self.syntax()).collect()
    }
    fn has_modifier(&self, kind: SyntaxKind) -> bool {
        self.modifiers().is_some_and(|m| m.has(kind))
    }
}

/// The lookups every accessor is made of.
pub(crate) mod support {
    use super::{AstChildren, AstNode};
    use crate::syntax::{SyntaxKind, SyntaxNode, SyntaxToken};

    // Each lookup scans the green children by kind and makes a syntax node (an allocation) only
    // for the child it returns: the typed accessors run per node of every check.

    /// First child node of type `N`.
    pub(crate) fn child<N: AstNode>(parent: &SyntaxNode) -> Option<N> {
        parent.first_child_by_kind(&N::can_cast).and_then(N::cast)
    }

    /// All child nodes of type `N`.
    pub(crate) fn children<N: AstNode>(parent: &SyntaxNode) -> AstChildren<N> {
        AstChildren { next: parent.first_child_by_kind(&N::can_cast), node: std::marker::PhantomData }
    }

    /// First child token of `kind` (a node of that kind does not count).
    pub(crate) fn token(parent: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxToken> {
        token_of(parent, &[kind])
    }

    /// First child token of any of `kinds`.
    pub(crate) fn token_of(parent: &SyntaxNode, kinds: &[SyntaxKind]) -> Option<SyntaxToken> {
        let mut element = parent.first_child_or_token_by_kind(&|k| kinds.contains(&k))?;
        loop {
            match element {
                rowan::NodeOrToken::Token(token) => return Some(token),
                rowan::NodeOrToken::Node(node) => {
                    element = node.next_sibling_or_token_by_kind(&|k| kinds.contains(&k))?
                }
            }
        }
    }
}
