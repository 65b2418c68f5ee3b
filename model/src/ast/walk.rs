//! Walks of activity nodes that know node containers (Sec. 9.2.2.3): a body's own descendants
//! without the nodes it holds, and a node with every node nested in it. Neither collects.

use super::{ActivityNode, AstNode};
use crate::syntax::{GuDsl, SyntaxKind::NODE_BODY, SyntaxNode};

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

/// The iterator of [`ActivityNode::and_nested`]: a preorder that enters only nodes and their
/// bodies.
pub struct AndNested {
    walk: rowan::api::Preorder<GuDsl>,
}

impl AndNested {
    pub(super) fn new(node: &ActivityNode) -> AndNested {
        AndNested { walk: node.syntax().preorder() }
    }
}

impl Iterator for AndNested {
    type Item = ActivityNode;

    fn next(&mut self) -> Option<ActivityNode> {
        loop {
            let rowan::WalkEvent::Enter(node) = self.walk.next()? else { continue };
            if let Some(activity_node) = ActivityNode::cast(node.clone()) {
                return Some(activity_node);
            }
            if node.kind() != NODE_BODY {
                self.walk.skip_subtree();
            }
        }
    }
}
