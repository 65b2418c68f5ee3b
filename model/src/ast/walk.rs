//! Walks of activity nodes that know node containers (Sec. 9.2.2.3): a body's own descendants
//! without the nodes it holds, and a node with every node nested in it. Neither collects.

use super::{ActivityNode, AstChildren, AstNode};
use crate::syntax::{GuDsl, SyntaxNode};

/// The descendants of `root` (itself included) outside the nodes nested in it: a node body's
/// own statements and transitions, not those of the nodes it holds (Sec. 9.2.2.3), which are
/// bodies of their own. As cheap as `descendants()`: nothing is collected.
pub fn own_descendants(root: &SyntaxNode) -> OwnDescendants {
    OwnDescendants { root: root.clone(), walk: root.preorder() }
}

/// The iterator of [`own_descendants`].
pub struct OwnDescendants {
    root: SyntaxNode,
    walk: rowan::api::Preorder<GuDsl>,
}

impl Iterator for OwnDescendants {
    type Item = SyntaxNode;

    fn next(&mut self) -> Option<SyntaxNode> {
        loop {
            match self.walk.next()? {
                rowan::WalkEvent::Enter(node) if node != self.root && ActivityNode::can_cast(node.kind()) => {
                    self.walk.skip_subtree();
                }
                rowan::WalkEvent::Enter(node) => return Some(node),
                rowan::WalkEvent::Leave(_) => {}
            }
        }
    }
}

/// The iterator of [`ActivityNode::and_nested`]: a depth-first walk that visits only nodes
/// and, below each, the nodes of its body (a stack of the bodies' node lists).
pub struct AndNested {
    first: Option<ActivityNode>,
    bodies: Vec<AstChildren<ActivityNode>>,
}

impl AndNested {
    pub(super) fn new(node: &ActivityNode) -> AndNested {
        AndNested { first: Some(node.clone()), bodies: Vec::new() }
    }
}

impl Iterator for AndNested {
    type Item = ActivityNode;

    fn next(&mut self) -> Option<ActivityNode> {
        let node = match self.first.take() {
            Some(node) => node,
            None => loop {
                let nodes = self.bodies.last_mut()?;
                match nodes.next() {
                    Some(node) => break node,
                    None => drop(self.bodies.pop()),
                }
            },
        };
        if let Some(body) = node.body() {
            self.bodies.push(body.nodes());
        }
        Some(node)
    }
}
