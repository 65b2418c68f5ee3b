//! Ranks: edges oriented so that the graph is acyclic, then each box's rank by network simplex
//! (`simplex`), started from longest-path ranks. A flow is oriented as it reads (depth-first
//! from its sources: a loop's edge back points up). Elsewhere which edges to reverse decides how
//! long the drawing is, and no one rule is best on every graph: three orientations are tried —
//! depth-first search from the sources, depth-first search in box order (as dot breaks cycles),
//! and Eades, Lin and Smyth's greedy feedback arc set — and those that reverse the fewest firm
//! edges are the candidates, by least total edge length, then fewest ranks (the layout keeps
//! the one its sweeps find the fewest crossings in).

use std::{cmp::Reverse, collections::BinaryHeap};

use super::{minimise::HUGE, parts::connected_parts, simplex};

/// Edges oriented so that the graph is acyclic, `(from, to, reversed)`, and each box's rank.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Ranked {
    pub edges: Vec<(usize, usize, bool)>,
    pub rank: Vec<usize>,
}

/// The ways to rank the boxes worth laying out, best guess first: for a flow the one it reads
/// as; otherwise those of the three orientations that reverse the fewest firm edges, each
/// once, by least total edge length, then fewest ranks (of a huge graph, only the first that
/// reverses the fewest). `flow` and `firm` as `LayoutInput` says.
/// With `wanted` ranks (per box, or none: a layout before's rows) the boxes keep them where the
/// edges allow (`kept`) instead of being ranked by network simplex.
pub(super) fn candidates(
    n: usize,
    edges: &[(usize, usize)],
    flow: bool,
    firm: &[bool],
    wanted: &[Option<usize>],
) -> Vec<Ranked> {
    let orientations = if flow {
        vec![depth_first(n, edges, true)]
    } else if n + edges.len() > HUGE {
        // Ranking each costs more than it may save: the first that reverses fewest firm edges.
        let mut all = vec![depth_first(n, edges, true), depth_first(n, edges, false), greedy(n, edges, firm)];
        let against = |reversed: &[bool]| reversed.iter().zip(firm).filter(|(&r, &f)| r && f).count();
        let fewest = (0..all.len()).min_by_key(|&i| against(&all[i])).expect("three orientations");
        vec![all.swap_remove(fewest)]
    } else {
        vec![depth_first(n, edges, true), depth_first(n, edges, false), greedy(n, edges, firm)]
    };
    // Where rows were kept, the edges between their boxes point as they did.
    let remembered =
        (!flow && !wanted.is_empty()).then(|| as_remembered(n, edges, firm, wanted, &orientations[0])).flatten();
    let orientations: Vec<Vec<bool>> = remembered.into_iter().chain(orientations).collect();
    let mut scored: Vec<((usize, usize, usize), Ranked)> = orientations
        .into_iter()
        .map(|reversed| {
            let against = reversed.iter().zip(firm).filter(|(&r, &f)| r && f).count();
            let oriented = turned(edges, reversed);
            let rank = match wanted.is_empty() {
                true => simplex::network_simplex(n, &oriented, &feasible_near(n, &oriented, &[])),
                false => kept(n, &oriented, wanted),
            };
            let length: usize = oriented.iter().filter(|e| e.0 != e.1).map(|e| rank[e.1] - rank[e.0]).sum();
            let height = rank.iter().max().map_or(0, |r| r + 1);
            ((against, length, height), Ranked { edges: oriented, rank })
        })
        .collect();
    scored.sort_by_key(|(key, _)| *key); // stable: of equals the first tried stays first
    let fewest_against = scored[0].0 .0;
    let mut kept: Vec<Ranked> = Vec::new();
    for (key, ranked) in scored {
        if key.0 == fewest_against && !kept.contains(&ranked) {
            kept.push(ranked);
        }
    }
    kept
}

/// Edges oriented so that the graph is acyclic by the first candidate alone (for tests that
/// need a proper graph without network simplex).
#[cfg(test)]
pub(super) fn orient(n: usize, edges: &[(usize, usize)]) -> Vec<(usize, usize, bool)> {
    turned(edges, depth_first(n, edges, true))
}

/// Which edges to reverse so that each edge between boxes in different `wanted` rows points down
/// from the higher one, and an edge between a box in a row and a new one (not firm) points to the
/// new one — below the rows, it pushes none of them down — unless the new box is a firm
/// parent of boxes in rows (it goes above them); the others as in `fallback`. None where that
/// makes a cycle.
fn as_remembered(
    n: usize,
    edges: &[(usize, usize)],
    firm: &[bool],
    wanted: &[Option<usize>],
    fallback: &[bool],
) -> Option<Vec<bool>> {
    let row = |v: usize| wanted.get(v).copied().flatten();
    let is_firm = |e: usize| firm.get(e).copied().unwrap_or(false);
    let mut parent_of_kept = vec![false; n];
    for (e, &(a, b)) in edges.iter().enumerate() {
        if is_firm(e) && row(a).is_none() && row(b).is_some() {
            parent_of_kept[a] = true;
        }
    }
    let reversed: Vec<bool> = edges
        .iter()
        .enumerate()
        .map(|(e, &(a, b))| match (row(a), row(b)) {
            (Some(ra), Some(rb)) if ra != rb => ra > rb,
            _ if is_firm(e) => fallback[e],
            // The new box above (a parent of boxes kept): it points down to the kept one.
            (Some(_), None) => parent_of_kept[b],
            (None, Some(_)) => !parent_of_kept[a],
            _ => fallback[e],
        })
        .collect();
    // Acyclic: a topological order takes every box.
    (topological(n, &turned(edges, reversed.clone())).0.len() == n).then_some(reversed)
}

/// `edges` with those marked `reversed` turned round: `(from, to, reversed)`.
fn turned(edges: &[(usize, usize)], reversed: Vec<bool>) -> Vec<(usize, usize, bool)> {
    edges.iter().zip(reversed).map(|(&(a, b), r)| if r { (b, a, true) } else { (a, b, false) }).collect()
}

/// Which edges close a cycle in a depth-first search that starts from each box in turn (the
/// sources first when `sources_first`).
fn depth_first(n: usize, edges: &[(usize, usize)], sources_first: bool) -> Vec<bool> {
    let mut out: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (i, &(a, b)) in edges.iter().enumerate() {
        out[a].push((b, i));
    }
    let mut state = vec![0u8; n]; // 0 new, 1 on stack, 2 done
    let mut reversed = vec![false; edges.len()];
    let mut roots: Vec<usize> = Vec::new();
    if sources_first {
        let mut indegree = vec![0usize; n];
        for &(_, b) in edges {
            indegree[b] += 1;
        }
        roots.extend((0..n).filter(|&v| indegree[v] == 0));
    }
    roots.extend(0..n);
    for root in roots {
        if state[root] != 0 {
            continue;
        }
        let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
        state[root] = 1;
        while let Some(&mut (v, ref mut next)) = stack.last_mut() {
            if let Some(&(w, edge)) = out[v].get(*next) {
                *next += 1;
                match state[w] {
                    0 => {
                        state[w] = 1;
                        stack.push((w, 0));
                    }
                    1 => reversed[edge] = true,
                    _ => {}
                }
            } else {
                state[v] = 2;
                stack.pop();
            }
        }
    }
    reversed
}

/// The edges that point backwards in Eades, Lin and Smyth's vertex sequence (1993): sinks are
/// taken to the end and sources to the front as they appear; otherwise the box with the most
/// more outgoing than incoming edges goes to the front (the lowest index among equals); then
/// reordered so that firm edges point forwards (`firm_first`).
fn greedy(n: usize, edges: &[(usize, usize)], firm: &[bool]) -> Vec<bool> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut into: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b) in edges.iter().filter(|e| e.0 != e.1) {
        out[a].push(b);
        into[b].push(a);
    }
    let mut outdegree: Vec<i64> = out.iter().map(|o| o.len() as i64).collect();
    let mut indegree: Vec<i64> = into.iter().map(|i| i.len() as i64).collect();
    let mut removed = vec![false; n];
    let (mut front, mut back) = (Vec::with_capacity(n), Vec::new());
    let mut left = n;
    let take = |v: usize, removed: &mut Vec<bool>, outdegree: &mut Vec<i64>, indegree: &mut Vec<i64>| {
        removed[v] = true;
        out[v].iter().for_each(|&w| indegree[w] -= 1);
        into[v].iter().for_each(|&u| outdegree[u] -= 1);
    };
    while left > 0 {
        let mut changed = true;
        while changed {
            changed = false;
            for v in 0..n {
                if !removed[v] && outdegree[v] == 0 {
                    take(v, &mut removed, &mut outdegree, &mut indegree);
                    back.push(v);
                    left -= 1;
                    changed = true;
                } else if !removed[v] && indegree[v] == 0 {
                    take(v, &mut removed, &mut outdegree, &mut indegree);
                    front.push(v);
                    left -= 1;
                    changed = true;
                }
            }
        }
        if let Some(v) = (0..n).filter(|&v| !removed[v]).max_by_key(|&v| (outdegree[v] - indegree[v], Reverse(v))) {
            take(v, &mut removed, &mut outdegree, &mut indegree);
            front.push(v);
            left -= 1;
        }
    }
    front.extend(back.into_iter().rev());
    let position = firm_first(n, edges, firm, &front);
    edges.iter().map(|&(a, b)| a != b && position[a] > position[b]).collect()
}

/// Each box's position in `sequence` reordered as little as makes every firm edge point
/// forwards: the earliest box in `sequence` whose firm predecessors are all placed goes next
/// (where firm edges close a cycle, the rest follow in `sequence`'s order).
fn firm_first(n: usize, edges: &[(usize, usize)], firm: &[bool], sequence: &[usize]) -> Vec<usize> {
    let mut at = vec![0usize; n];
    for (i, &v) in sequence.iter().enumerate() {
        at[v] = i;
    }
    let mut waiting = vec![0usize; n];
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (&(a, b), _) in edges.iter().zip(firm).filter(|(e, &f)| f && e.0 != e.1) {
        waiting[b] += 1;
        after[a].push(b);
    }
    let mut ready: BinaryHeap<Reverse<usize>> = (0..n).filter(|&v| waiting[v] == 0).map(|v| Reverse(at[v])).collect();
    let mut placed = vec![false; n];
    let mut position = vec![0usize; n];
    let mut next = 0;
    while let Some(Reverse(i)) = ready.pop() {
        let v = sequence[i];
        (placed[v], position[v], next) = (true, next, next + 1);
        for &w in &after[v] {
            waiting[w] -= 1;
            if waiting[w] == 0 {
                ready.push(Reverse(at[w]));
            }
        }
    }
    for &v in sequence.iter().filter(|&&v| !placed[v]) {
        (position[v], next) = (next, next + 1);
    }
    position
}

/// Each box's rank: the length of the longest path to it from a source (feasible ranks).
#[cfg(test)]
pub(super) fn longest_path(n: usize, edges: &[(usize, usize, bool)]) -> Vec<usize> {
    feasible_near(n, edges, &[])
}

/// Ranks that keep the `wanted` ones (a layout before's rows) where the edges allow: each box
/// at its wanted rank or lower where an edge into it asks; a box without one (new) just below
/// the boxes its edges come from, or, where none do, just above the highest box they go to.
fn kept(n: usize, edges: &[(usize, usize, bool)], wanted: &[Option<usize>]) -> Vec<usize> {
    let mut rank = feasible_near(n, edges, wanted);
    let new = |v: usize| wanted.get(v).copied().flatten().is_none();
    let mut sources = vec![true; n];
    let mut highest_below = vec![usize::MAX; n];
    for &(a, b, _) in edges.iter().filter(|e| e.0 != e.1) {
        sources[b] = false;
        highest_below[a] = highest_below[a].min(rank[b]);
    }
    for v in (0..n).filter(|&v| new(v) && sources[v] && highest_below[v] != usize::MAX) {
        rank[v] = highest_below[v].saturating_sub(1).max(rank[v]);
    }
    top_at_zero(n, edges, rank)
}

/// `rank` moved up so that each connected part's top rank is 0, as network simplex leaves it.
fn top_at_zero(n: usize, edges: &[(usize, usize, bool)], mut rank: Vec<usize>) -> Vec<usize> {
    let roots = connected_parts(n, edges.iter().map(|&(a, b, _)| (a, b)));
    let mut top = vec![usize::MAX; n];
    for (&r, &at) in roots.iter().zip(&rank) {
        top[r] = top[r].min(at);
    }
    for (at, &r) in rank.iter_mut().zip(&roots) {
        *at -= top[r];
    }
    rank
}

/// Feasible ranks (every edge pointing down) nearest `wanted` from above: each box at its wanted
/// rank (0 where none is), or lower where an edge into it asks. Without any wanted rank: the
/// length of the longest path to each box from a source.
pub(super) fn feasible_near(n: usize, edges: &[(usize, usize, bool)], wanted: &[Option<usize>]) -> Vec<usize> {
    let mut rank: Vec<usize> = (0..n).map(|v| wanted.get(v).copied().flatten().unwrap_or(0)).collect();
    let (order, out) = topological(n, edges);
    for v in order {
        for &w in &out[v] {
            rank[w] = rank[w].max(rank[v] + 1);
        }
    }
    rank
}

/// The boxes in an order where every edge (self loops aside) points forward, breadth first from
/// the sources (Kahn), and each box's successors; fewer than `n` boxes where edges make a cycle.
fn topological(n: usize, edges: &[(usize, usize, bool)]) -> (Vec<usize>, Vec<Vec<usize>>) {
    let mut indegree = vec![0usize; n];
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b, _) in edges.iter().filter(|e| e.0 != e.1) {
        indegree[b] += 1;
        out[a].push(b);
    }
    let mut order: Vec<usize> = (0..n).filter(|&v| indegree[v] == 0).collect();
    let mut next = 0;
    while let Some(&v) = order.get(next) {
        next += 1;
        for &w in &out[v] {
            indegree[w] -= 1;
            if indegree[w] == 0 {
                order.push(w);
            }
        }
    }
    (order, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first candidate.
    fn ranks(n: usize, edges: &[(usize, usize)], flow: bool, firm: &[bool]) -> (Vec<(usize, usize, bool)>, Vec<usize>) {
        let Ranked { edges, rank } = candidates(n, edges, flow, firm, &[]).remove(0);
        (edges, rank)
    }

    fn total_length(edges: &[(usize, usize, bool)], rank: &[usize]) -> usize {
        edges.iter().filter(|e| e.0 != e.1).map(|e| rank[e.1] - rank[e.0]).sum()
    }

    #[test]
    fn a_flow_reads_from_its_start_and_its_loop_goes_back_up() {
        // start 0 -> 1 -> 2 -> 3 -> 4 (the end), 3 -> 1 the loop's edge back: only it points up,
        // though drawing 1 -> 2 upwards would be as short.
        let edges = [(0, 1), (1, 2), (2, 3), (3, 4), (3, 1)];
        let (oriented, rank) = ranks(5, &edges, true, &[]);
        assert_eq!(oriented.iter().map(|e| e.2).collect::<Vec<_>>(), [false, false, false, false, true]);
        assert_eq!(rank, [0, 1, 2, 3, 4]);
    }

    #[test]
    fn a_generalization_in_a_cycle_still_points_down() {
        // 0 is the superclass of 1 (laid out 0 -> 1, firm); associations 1 -> 2 -> 0 close a
        // cycle, which a search from box 0 or 1 would close with the generalization.
        let edges = [(2, 0), (0, 1), (1, 2)];
        let (oriented, rank) = ranks(3, &edges, false, &[false, true, false]);
        assert!(!oriented[1].2);
        assert!(rank[0] < rank[1]);
    }

    #[test]
    fn the_first_candidate_is_the_shortest_of_the_three() {
        // Pseudo-random graphs with cycles: every edge points down, the ranks kept are never
        // longer than the search from the sources gives, and on some strictly shorter.
        let mut shorter = 0;
        for seed in 0..20u64 {
            let n = 40;
            let edges = crate::layout::tests::pseudo_random_edges(seed + 100, n, 60);
            let (oriented, rank) = ranks(n, &edges, false, &[]);
            assert!(oriented.iter().filter(|e| e.0 != e.1).all(|e| rank[e.1] > rank[e.0]));
            let length = total_length(&oriented, &rank);
            // As a flow, the search from the sources is the only candidate.
            let (from_sources, its_rank) = ranks(n, &edges, true, &[]);
            let searched = total_length(&from_sources, &its_rank);
            assert!(length <= searched);
            shorter += usize::from(length < searched);
        }
        assert!(shorter > 0);
    }
}
