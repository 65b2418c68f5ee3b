//! Ranks by the network simplex method (Gansner, Koutsofios, North, Vo: A Technique for Drawing
//! Directed Graphs, 1993 — what Graphviz `dot` ranks with): from feasible ranks, a spanning tree
//! of tight edges per connected part, then tree edges with a negative cut value exchanged for
//! the non-tree edge of least slack across the cut until none is left. The result keeps every
//! edge pointing down and makes the edges' total length least: fewer dummies, fewer crossings,
//! a shorter drawing than longest-path ranks.

/// Ranks of `n` boxes under `edges` (oriented so that the graph is acyclic; self loops are
/// ignored), starting from the feasible `rank`; each connected part's top rank is 0.
pub(super) fn network_simplex(n: usize, edges: &[(usize, usize, bool)], rank: &[usize]) -> Vec<usize> {
    let mut simplex = Simplex::new(n, edges, rank);
    // Each exchange shortens the total edge length, so this ends; the bound (ELK's, 28 √n)
    // keeps huge inputs fast, leaving their ranks feasible but perhaps not least.
    let mut start = 0;
    for _ in 0..((28.0 * (n as f64).sqrt()) as usize).max(100) {
        let Some((leaving, next)) = simplex.leaving_arc(start) else { break };
        start = next;
        let Some(entering) = simplex.entering_arc(leaving) else { break };
        simplex.exchange(leaving, entering);
    }
    simplex.normalised()
}

struct Simplex {
    rank: Vec<i64>,
    arcs: Vec<(usize, usize)>,
    /// Arc indices per box.
    incident: Vec<Vec<usize>>,
    in_tree: Vec<bool>,
    tree: Tree,
}

/// The spanning forest rooted at each part's first box, numbered in postorder: box `v` lies in
/// the subtree of `c` exactly when `low[c] <= lim[v] <= lim[c]`.
#[derive(Debug, Default, PartialEq)]
struct Tree {
    /// The tree arc to each box's parent (`None` at a root).
    parent_arc: Vec<Option<usize>>,
    lim: Vec<usize>,
    low: Vec<usize>,
    /// Boxes by postorder number.
    order: Vec<usize>,
}

impl Tree {
    fn of(s: &Simplex) -> Tree {
        let n = s.rank.len();
        let mut tree =
            Tree { parent_arc: vec![None; n], lim: vec![0; n], low: vec![0; n], order: Vec::with_capacity(n) };
        let mut seen = vec![false; n];
        for root in 0..n {
            if !seen[root] {
                tree.walk(s, root, &mut seen);
            }
        }
        tree
    }

    /// Numbers the subtree of `top` again after an exchange inside it, from its first number
    /// on, as a walk of the whole forest would: the boxes outside keep theirs.
    fn number_from(&mut self, s: &Simplex, top: usize) {
        let (first, last) = (self.low[top], self.lim[top]);
        let mut seen = vec![false; s.rank.len()];
        // Every box outside the subtree counts as seen (the way up from `top` among them).
        self.order[..first].iter().chain(&self.order[last + 1..]).for_each(|&v| seen[v] = true);
        let after = self.order.split_off(last + 1);
        self.order.truncate(first);
        self.walk(s, top, &mut seen);
        self.order.extend(after);
    }

    /// Depth-first from `root` along tree arcs to boxes not yet `seen`, numbering each box in
    /// postorder from `order.len()`.
    fn walk(&mut self, s: &Simplex, root: usize, seen: &mut [bool]) {
        seen[root] = true;
        // (box, next incident arc to look at, lowest postorder number below it)
        let mut stack: Vec<(usize, usize, usize)> = vec![(root, 0, usize::MAX)];
        while let Some(top) = stack.last_mut() {
            let (v, next) = (top.0, top.1);
            if let Some(&arc) = s.incident[v].get(next) {
                top.1 += 1;
                let (a, b) = s.arcs[arc];
                let w = if a == v { b } else { a };
                if s.in_tree[arc] && !seen[w] {
                    seen[w] = true;
                    self.parent_arc[w] = Some(arc);
                    stack.push((w, 0, usize::MAX));
                }
            } else {
                let number = self.order.len();
                let low = top.2.min(number);
                self.lim[v] = number;
                self.low[v] = low;
                self.order.push(v);
                stack.pop();
                if let Some(parent) = stack.last_mut() {
                    parent.2 = parent.2.min(low);
                }
            }
        }
    }

    fn below(&self, c: usize, v: usize) -> bool {
        self.low[c] <= self.lim[v] && self.lim[v] <= self.lim[c]
    }

    /// The boxes of `c`'s subtree.
    fn subtree(&self, c: usize) -> &[usize] {
        &self.order[self.low[c]..=self.lim[c]]
    }
}

impl Simplex {
    /// The arcs of `edges` (self loops left out) from the feasible `rank`, with a feasible tree.
    fn new(n: usize, edges: &[(usize, usize, bool)], rank: &[usize]) -> Simplex {
        let arcs: Vec<(usize, usize)> = edges.iter().filter(|e| e.0 != e.1).map(|&(a, b, _)| (a, b)).collect();
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, &(a, b)) in arcs.iter().enumerate() {
            incident[a].push(i);
            incident[b].push(i);
        }
        let mut simplex = Simplex {
            rank: rank.iter().map(|&r| r as i64).collect(),
            in_tree: vec![false; arcs.len()],
            arcs,
            incident,
            tree: Tree::default(),
        };
        simplex.feasible_tree();
        simplex.tree = Tree::of(&simplex);
        simplex
    }

    fn slack(&self, arc: usize) -> i64 {
        let (a, b) = self.arcs[arc];
        self.rank[b] - self.rank[a] - 1
    }

    /// Grows a tree of tight arcs in each connected part, shifting the tree by the least slack
    /// of the arcs leaving it until it spans the part.
    fn feasible_tree(&mut self) {
        let n = self.rank.len();
        let mut in_tree_box = vec![false; n];
        for root in 0..n {
            if in_tree_box[root] {
                continue;
            }
            in_tree_box[root] = true;
            let mut members = vec![root];
            loop {
                // Every box reachable from the tree by tight arcs joins it.
                let mut k = 0;
                while k < members.len() {
                    let v = members[k];
                    for &arc in &self.incident[v] {
                        let (a, b) = self.arcs[arc];
                        let w = if a == v { b } else { a };
                        if !in_tree_box[w] && self.slack(arc) == 0 {
                            in_tree_box[w] = true;
                            self.in_tree[arc] = true;
                            members.push(w);
                        }
                    }
                    k += 1;
                }
                // The arc with the least slack between the tree and the rest of its part.
                let closest = members
                    .iter()
                    .flat_map(|&v| self.incident[v].iter().map(move |&arc| (v, arc)))
                    .filter(|&(_, arc)| {
                        let (a, b) = self.arcs[arc];
                        in_tree_box[a] != in_tree_box[b]
                    })
                    .min_by_key(|&(_, arc)| (self.slack(arc), arc));
                let Some((inside, arc)) = closest else { break };
                let delta = if self.arcs[arc].0 == inside { self.slack(arc) } else { -self.slack(arc) };
                for &v in &members {
                    self.rank[v] += delta;
                }
            }
        }
    }

    /// A tree arc whose cut value is negative, looking from `start` round: the arc and where to
    /// look next time.
    fn leaving_arc(&self, start: usize) -> Option<(usize, usize)> {
        let m = self.arcs.len();
        let net = self.net_outflow();
        (0..m)
            .map(|k| (start + k) % m)
            .find(|&arc| self.in_tree[arc] && self.cut_value(arc, &net) < 0)
            .map(|arc| (arc, arc + 1))
    }

    /// Per box, the arcs leaving its subtree less the arcs entering it (arcs inside the
    /// subtree count once each way): O(boxes + arcs) for every tree arc's cut value.
    fn net_outflow(&self) -> Vec<i64> {
        let mut net = vec![0i64; self.rank.len()];
        for &(a, b) in &self.arcs {
            net[a] += 1;
            net[b] -= 1;
        }
        for &v in &self.tree.order {
            if let Some(arc) = self.tree.parent_arc[v] {
                let (a, b) = self.arcs[arc];
                let parent = if a == v { b } else { a };
                net[parent] += net[v];
            }
        }
        net
    }

    /// The box on the subtree side of tree arc `arc`.
    fn child(&self, arc: usize) -> usize {
        let (a, b) = self.arcs[arc];
        if self.tree.parent_arc[b] == Some(arc) {
            b
        } else {
            a
        }
    }

    /// The arcs' weight from the tree arc's tail side to its head side, less the weight back:
    /// the subtree's net outflow, counted the tree arc's way (out of the subtree where the arc
    /// points out of it, into it where the arc points in).
    fn cut_value(&self, arc: usize, net: &[i64]) -> i64 {
        let c = self.child(arc);
        if c == self.arcs[arc].0 {
            net[c]
        } else {
            -net[c]
        }
    }

    /// The non-tree arc of least slack from the leaving arc's head side to its tail side.
    fn entering_arc(&self, leaving: usize) -> Option<usize> {
        let c = self.child(leaving);
        let head_below = c == self.arcs[leaving].1;
        let head_side = |v: usize| self.tree.below(c, v) == head_below;
        // Only arcs of the same part can cross the cut, and they touch the subtree.
        self.tree
            .subtree(c)
            .iter()
            .flat_map(|&v| &self.incident[v])
            .copied()
            .filter(|&arc| {
                let (a, b) = self.arcs[arc];
                !self.in_tree[arc] && head_side(a) && !head_side(b)
            })
            .min_by_key(|&arc| (self.slack(arc), arc))
    }

    fn exchange(&mut self, leaving: usize, entering: usize) {
        let c = self.child(leaving);
        let head_below = c == self.arcs[leaving].1;
        // Make the entering arc tight by moving the subtree: down if it is the head side.
        let delta = if head_below { self.slack(entering) } else { -self.slack(entering) };
        let subtree: Vec<usize> = self.tree.subtree(c).to_vec();
        for v in subtree {
            self.rank[v] += delta;
        }
        // Only the subtree of the entering arc's ends' lowest common ancestor changes (the
        // leaving arc lies on the path between them): it is numbered again from where it began.
        let (a, b) = self.arcs[entering];
        let mut top = a;
        while !self.tree.below(top, b) {
            let arc = self.tree.parent_arc[top].expect("the ends of an arc share a tree");
            top = if self.arcs[arc].0 == top { self.arcs[arc].1 } else { self.arcs[arc].0 };
        }
        self.in_tree[leaving] = false;
        self.in_tree[entering] = true;
        let mut tree = std::mem::take(&mut self.tree);
        tree.number_from(self, top);
        self.tree = tree;
    }

    /// Ranks with each connected part's top at 0 (a part is its tree root's subtree).
    fn normalised(&self) -> Vec<usize> {
        let mut rank = vec![0; self.rank.len()];
        for root in (0..self.rank.len()).filter(|&v| self.tree.parent_arc[v].is_none()) {
            let part = self.tree.subtree(root);
            let top = part.iter().map(|&v| self.rank[v]).min().unwrap_or(0);
            for &v in part {
                rank[v] = (self.rank[v] - top) as usize;
            }
        }
        rank
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{rank, tests::pseudo_random_edges};

    #[test]
    fn an_exchange_renumbers_the_tree_as_a_whole_walk_would() {
        let mut exchanges = 0;
        for seed in 0..24 {
            let n = 40 + (seed as usize % 4) * 20;
            let edges = rank::orient(n, &pseudo_random_edges(seed, n, n * 3 / 2));
            let mut simplex = Simplex::new(n, &edges, &rank::longest_path(n, &edges));
            let mut start = 0;
            while let Some((leaving, next)) = simplex.leaving_arc(start) {
                start = next;
                let Some(entering) = simplex.entering_arc(leaving) else { break };
                simplex.exchange(leaving, entering);
                assert_eq!(simplex.tree, Tree::of(&simplex), "seed {seed}, exchange {exchanges}");
                exchanges += 1;
            }
        }
        assert!(exchanges > 50, "only {exchanges} exchanges: the test would prove little");
    }
}
