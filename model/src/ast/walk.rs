//! Walks of activity nodes that know node containers (Sec. 9.2.2.3): a body's own descendants
//! without the nodes it holds, and a node with every node nested in it. Neither collects.

use super::{ActivityNode, AstChildren, AstNode};
use rowan::Language;

use crate::syntax::{GuDsl, SyntaxKind, SyntaxNode};

/// The descendants of `root` (itself included) outside the nodes nested in it: a node body's
/// own statements and transitions, not those of the nodes it holds (Sec. 9.2.2.3), which are
/// bodies of their own. As cheap as `descendants()`: nothing is collected.
pub fn own_descendants(root: &SyntaxNode) -> OwnDescendants {
    OwnDescendants { root: root.clone(), walk: root.preorder() }
}

/// Whether the own descendants of `root` (as [`own_descendants`] walks them, `root` included)
/// hold at least `at_least` nodes of a kind `wanted` accepts. It reads the green tree and makes
/// no syntax node, so a rule skips at little cost a walk that could find nothing.
pub fn owns_at_least(root: &SyntaxNode, at_least: usize, wanted: impl Fn(SyntaxKind) -> bool) -> bool {
    let mut left = at_least;
    if wanted(root.kind()) {
        left = left.saturating_sub(1);
    }
    left == 0 || green_owns(&root.green(), &mut left, &wanted)
}

/// [`owns_at_least`] below one green node: counts `left` down, true once it reaches zero.
fn green_owns(node: &rowan::GreenNodeData, left: &mut usize, wanted: &impl Fn(SyntaxKind) -> bool) -> bool {
    for child in node.children().filter_map(|c| c.into_node()) {
        let kind = GuDsl::kind_from_raw(child.kind());
        if ActivityNode::can_cast(kind) {
            continue;
        }
        if wanted(kind) {
            *left -= 1;
            if *left == 0 {
                return true;
            }
        }
        if green_owns(child, left, wanted) {
            return true;
        }
    }
    false
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
