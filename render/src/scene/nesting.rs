//! Nested nodes drawn inside their parents (components nest to any depth, §11.3.2; activity
//! nodes hold nodes, §9.2.2.3): each parent's children are laid out as a diagram of their own
//! (left to right for components, top down for activities), the parent grows to hold them
//! under its header, port rows and compartments, and they move with it; the top level is laid
//! out with each tree as its root's box.

use gudsl_model::graph::Graph;

use super::{measure::Content, Point};
use crate::layout::{Entry, Layout, LayoutInput, LayoutNode, Page, RowEntry, Spacing};

/// An edge laid out inside a parent: the parent, the route and the label's place from the
/// parent's corner.
type InnerRoute = (usize, Vec<Point>, Option<Point>);

/// Which node holds which.
pub(super) struct Nesting {
    /// Each node's parent, if it is nested.
    parent: Vec<Option<usize>>,
    /// Where each nested node's box lies from its parent's top-left corner.
    offset: Vec<Point>,
}

impl Nesting {
    pub(super) fn of(graph: &Graph) -> Nesting {
        let index = |id: &String| graph.nodes.iter().position(|n| &n.id == id);
        let mut parent: Vec<Option<usize>> = graph.nodes.iter().map(|n| n.parent.as_ref().and_then(index)).collect();
        // A cycle (two components of one class, one in the other) would nest forever: such a
        // node is drawn at the top level.
        for node in 0..parent.len() {
            let mut seen = vec![node];
            let mut at = parent[node];
            while let Some(p) = at {
                if seen.contains(&p) {
                    parent[node] = None;
                    break;
                }
                seen.push(p);
                at = parent[p];
            }
        }
        let offset = vec![Point::default(); parent.len()];
        Nesting { parent, offset }
    }

    pub(super) fn is_flat(&self) -> bool {
        self.parent.iter().all(Option::is_none)
    }

    pub(super) fn is_nested(&self, node: usize) -> bool {
        self.parent[node].is_some()
    }

    /// The node and its ancestors, innermost first.
    pub(super) fn lineage(&self, node: usize) -> impl Iterator<Item = usize> + '_ {
        std::iter::successors(Some(node), |&n| self.parent[n])
    }

    /// The nodes that hold both `a` and `b` or are one of them and hold the other.
    pub(super) fn holding_both(&self, a: usize, b: usize) -> Vec<usize> {
        self.lineage(a).filter(|&n| self.lineage(b).any(|m| m == n) && (n != a || n != b)).collect()
    }

    /// The ancestor of `node` (or the node) that lies directly in `level` (`None`: the top).
    fn in_level(&self, node: usize, level: Option<usize>) -> Option<usize> {
        self.lineage(node).find(|&n| self.parent[n] == level)
    }

    /// Each node's depth (0: the top level).
    fn depth(&self, node: usize) -> usize {
        self.lineage(node).count() - 1
    }

    /// Lays out a component diagram's nodes with their nesting: innermost parents first, each
    /// one's children as a left-to-right diagram inside it, then the top level. `input` holds
    /// every node (its box with the room its port symbols take, `reaches`) and edge;
    /// `contents` grow to hold their children. The result is in `layered`'s terms: layout
    /// boxes' corners and routes for every node and edge (a route between a node and its own
    /// ancestor, a delegation, is left to the connection router).
    pub(super) fn layout(
        &mut self,
        input: &LayoutInput,
        contents: &mut [Content],
        reaches: &[(f64, f64)],
        spacing: Spacing,
        lay: fn(&LayoutInput, Spacing) -> Layout,
    ) -> Layout {
        let n = self.parent.len();
        let mut parents: Vec<usize> = (0..n).filter(|&p| self.parent.contains(&Some(p))).collect();
        parents.sort_by_key(|&p| std::cmp::Reverse(self.depth(p)));
        // Routes (and label places) of edges laid out inside a parent, from the parent's corner.
        let mut inner_routes: Vec<Option<InnerRoute>> = vec![None; input.edges.len()];
        // The rows of each parent's inside, innermost first; the top level's go before them.
        let mut inner_rows: Vec<Vec<RowEntry>> = Vec::new();
        let layout_box = |contents: &[Content], v: usize| LayoutNode {
            width: reaches[v].0 + contents[v].width + reaches[v].1,
            height: contents[v].height,
        };
        for parent in parents {
            let (level, sub, edges) = self.level(input, Some(parent), |v| layout_box(contents, v));
            // A component's inside is as its ranks come: only the whole drawing is fitted to the page.
            let inner = lay(&sub, Spacing { page: Page::UNBOUNDED, ..spacing });
            inner_rows.extend(inner.rows.iter().map(|row| row.iter().map(|e| outer(e, &level, &edges)).collect()));
            let top = contents[parent].height;
            for (&child, at) in level.iter().zip(&inner.positions) {
                self.offset[child] = Point { x: at.x + reaches[child].0, y: top + at.y };
            }
            let down = |p: &Point| Point { x: p.x, y: top + p.y };
            for ((&k, route), label) in edges.iter().zip(&inner.edges).zip(&inner.labels) {
                inner_routes[k] = Some((parent, route.iter().map(down).collect(), label.as_ref().map(down)));
            }
            let content = &mut contents[parent];
            content.width = content.width.max(inner.width);
            content.height += inner.height;
            content.nested = inner.height;
        }
        let (level, top_input, edges) = self.level(input, None, |v| layout_box(contents, v));
        let top = lay(&top_input, spacing);
        let rows: Vec<Vec<RowEntry>> = top
            .rows
            .iter()
            .map(|row| row.iter().map(|e| outer(e, &level, &edges)).collect())
            .chain(inner_rows)
            .collect();
        // Every box's corner: the top level's from its layout, the nested ones' from their parents.
        let mut corners = vec![Point::default(); n];
        for (&v, at) in level.iter().zip(&top.positions) {
            corners[v] = Point { x: at.x + reaches[v].0, y: at.y };
        }
        self.follow(&mut corners);
        let mut edge_routes = vec![Vec::new(); input.edges.len()];
        let mut labels = vec![None; input.edges.len()];
        for ((&k, route), label) in edges.iter().zip(top.edges).zip(top.labels) {
            edge_routes[k] = route;
            labels[k] = label;
        }
        for (k, inner) in inner_routes.into_iter().enumerate() {
            if let Some((parent, route, label)) = inner {
                let at = corners[parent];
                let moved = |p: Point| Point { x: at.x + p.x, y: at.y + p.y };
                edge_routes[k] = route.into_iter().map(moved).collect();
                labels[k] = label.map(moved);
            }
        }
        Layout {
            positions: corners.iter().zip(reaches).map(|(c, r)| Point { x: c.x - r.0, y: c.y }).collect(),
            edges: edge_routes,
            // Labels the layout placed (top-down layouts do); the others are placed afterwards.
            labels,
            end_labels: vec![[None; 2]; input.edges.len()],
            width: top.width,
            height: top.height,
            rows,
        }
    }

    /// Moves every nested node's box corner (in `corners`, one per node) to its place in its
    /// parent, outermost first, wherever the parent is.
    pub(super) fn follow(&self, corners: &mut [Point]) {
        let mut nested: Vec<usize> = (0..corners.len()).filter(|&v| self.parent[v].is_some()).collect();
        nested.sort_by_key(|&v| self.depth(v));
        for v in nested {
            let parent = corners[self.parent[v].expect("nested")];
            corners[v] = Point { x: parent.x + self.offset[v].x, y: parent.y + self.offset[v].y };
        }
    }

    /// The nodes directly in `level`, the layout input of their boxes (`size`) and the edges
    /// between them — an edge between two of their descendants counts as one between them —
    /// and which of `input`'s edges those are.
    fn level(
        &self,
        input: &LayoutInput,
        level: Option<usize>,
        size: impl Fn(usize) -> LayoutNode,
    ) -> (Vec<usize>, LayoutInput, Vec<usize>) {
        let members: Vec<usize> = (0..self.parent.len()).filter(|&v| self.parent[v] == level).collect();
        let local = |v: usize| {
            let at = self.in_level(v, level)?;
            members.iter().position(|&m| m == at)
        };
        let mut edges = Vec::new();
        let mut which = Vec::new();
        for (k, &(from, to)) in input.edges.iter().enumerate() {
            if let (Some(a), Some(b)) = (local(from), local(to)) {
                if a != b {
                    edges.push((a, b));
                    which.push(k);
                }
            }
        }
        // Swimlanes group the top level; a node's nested nodes are in its lane already.
        let groups =
            members.iter().map(|&v| if level.is_none() { input.groups.get(v).copied().flatten() } else { None });
        let sub = LayoutInput {
            nodes: members.iter().map(|&v| size(v)).collect(),
            labels: which.iter().map(|&k| input.labels.get(k).copied().flatten()).collect(),
            groups: groups.collect(),
            edges,
            flow: input.flow,
            firm: Vec::new(),
            end_labels: Vec::new(),
            ports: Vec::new(),
            remembered: input.remembered.part(&members, &which),
        };
        (members, sub, which)
    }
}

/// A row entry of one level's layout (`level`: its nodes, `edges`: its edges, as the whole
/// graph's indices) as the whole graph's.
fn outer(&(entry, x, y): &RowEntry, level: &[usize], edges: &[usize]) -> RowEntry {
    match entry {
        Entry::Box(i) => (Entry::Box(level[i]), x, y),
        Entry::Edge(i) => (Entry::Edge(edges[i]), x, y),
        Entry::Band | Entry::Column => (entry, x, y),
    }
}
