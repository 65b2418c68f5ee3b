//! The proper layered graph: every edge split by dummy vertices into segments that join
//! adjacent ranks, with the blocks that crossing minimisation moves as a whole (a box alone, or
//! all the dummies of one long edge).

use std::collections::VecDeque;

/// Boxes are the first vertices, in input order; dummies follow.
pub(super) struct Proper {
    pub boxes: usize,
    /// Rank per vertex.
    pub rank: Vec<usize>,
    /// Swimlane per vertex (`usize::MAX` for none); a dummy is in its edge's source's lane.
    pub group: Vec<usize>,
    /// Neighbours in the rank above, per vertex.
    pub up: Vec<Vec<usize>>,
    /// Neighbours in the rank below, per vertex.
    pub down: Vec<Vec<usize>>,
    /// Per oriented edge: its vertices from source to target (`[v, v]` for a self loop).
    pub chains: Vec<Vec<usize>>,
    /// A box alone, or the dummies of one long edge, top to bottom.
    pub blocks: Vec<Vec<usize>>,
    /// Block per vertex.
    pub block_of: Vec<usize>,
}

impl Proper {
    /// Splits the oriented `edges` of `groups.len()` boxes ranked by `rank`.
    pub fn new(groups: &[Option<usize>], edges: &[(usize, usize, bool)], rank: &[usize]) -> Proper {
        let boxes = rank.len();
        let mut vertex_rank = rank.to_vec();
        let mut group: Vec<usize> =
            (0..boxes).map(|v| groups.get(v).copied().flatten().unwrap_or(usize::MAX)).collect();
        let mut chains = Vec::with_capacity(edges.len());
        let mut segments = Vec::new();
        for &(a, b, _) in edges {
            if a == b {
                chains.push(vec![a, b]);
                continue;
            }
            let mut chain = vec![a];
            for r in rank[a] + 1..rank[b] {
                let dummy = vertex_rank.len();
                vertex_rank.push(r);
                group.push(group[a]);
                segments.push((chain[chain.len() - 1], dummy));
                chain.push(dummy);
            }
            segments.push((chain[chain.len() - 1], b));
            chain.push(b);
            chains.push(chain);
        }
        let vertices = vertex_rank.len();
        let (mut up, mut down) = (vec![Vec::new(); vertices], vec![Vec::new(); vertices]);
        for &(a, b) in &segments {
            down[a].push(b);
            up[b].push(a);
        }
        let mut blocks: Vec<Vec<usize>> = (0..boxes).map(|v| vec![v]).collect();
        blocks.extend(chains.iter().filter(|chain| chain.len() > 2).map(|chain| chain[1..chain.len() - 1].to_vec()));
        let mut block_of = vec![0; vertices];
        for (b, members) in blocks.iter().enumerate() {
            for &v in members {
                block_of[v] = b;
            }
        }
        Proper { boxes, rank: vertex_rank, group, up, down, chains, blocks, block_of }
    }

    pub fn vertices(&self) -> usize {
        self.rank.len()
    }

    pub fn ranks(&self) -> usize {
        self.rank.iter().max().map_or(0, |m| m + 1)
    }

    /// The vertices of each rank in breadth-first (else depth-first) order from the sources,
    /// along the edges downwards (or `undirected`, both ways, as dot starts): starts for
    /// crossing minimisation.
    pub fn initial_layers(&self, breadth_first: bool, undirected: bool) -> Vec<Vec<usize>> {
        let mut layers = vec![Vec::new(); self.ranks()];
        let mut seen = vec![false; self.vertices()];
        for root in (0..self.vertices()).filter(|&v| self.up[v].is_empty()).chain(0..self.vertices()) {
            if seen[root] {
                continue;
            }
            seen[root] = true;
            let mut pending = VecDeque::from([root]);
            while let Some(v) = if breadth_first { pending.pop_front() } else { pending.pop_back() } {
                layers[self.rank[v]].push(v);
                // Depth first visits the first neighbour first: push them in reverse.
                let neighbours = self.down[v].iter().chain(if undirected { &self.up[v] } else { &[][..] });
                let mut next: Vec<usize> = Vec::new();
                for &w in neighbours {
                    // A neighbour twice (parallel edges) is visited once.
                    if !seen[w] {
                        seen[w] = true;
                        next.push(w);
                    }
                }
                if breadth_first {
                    pending.extend(next);
                } else {
                    pending.extend(next.into_iter().rev());
                }
            }
        }
        layers
    }
}
