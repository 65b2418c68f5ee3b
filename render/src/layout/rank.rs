//! Ranks: edges oriented so that the graph is acyclic (reversing the edges that close a cycle in
//! a depth-first search from the sources), then each box's rank by the longest path to it: the
//! feasible ranks network simplex (`simplex`) starts from.

use std::collections::VecDeque;

/// Edges oriented so that the graph is acyclic: `(from, to, reversed)`.
pub(super) fn orient(n: usize, edges: &[(usize, usize)]) -> Vec<(usize, usize, bool)> {
    let mut out: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (i, &(a, b)) in edges.iter().enumerate() {
        out[a].push((b, i));
    }
    let mut state = vec![0u8; n]; // 0 new, 1 on stack, 2 done
    let mut reversed = vec![false; edges.len()];
    let mut indegree = vec![0usize; n];
    for &(_, b) in edges {
        indegree[b] += 1;
    }
    let mut roots: Vec<usize> = (0..n).filter(|&v| indegree[v] == 0).collect();
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
    edges.iter().zip(reversed).map(|(&(a, b), r)| if r { (b, a, true) } else { (a, b, false) }).collect()
}

/// Each box's rank: the length of the longest path to it from a source.
pub(super) fn longest_path(n: usize, edges: &[(usize, usize, bool)]) -> Vec<usize> {
    let mut indegree = vec![0usize; n];
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b, _) in edges {
        if a != b {
            indegree[b] += 1;
            out[a].push(b);
        }
    }
    let mut rank = vec![0usize; n];
    let mut queue: VecDeque<usize> = (0..n).filter(|&v| indegree[v] == 0).collect();
    while let Some(v) = queue.pop_front() {
        for &w in &out[v] {
            rank[w] = rank[w].max(rank[v] + 1);
            indegree[w] -= 1;
            if indegree[w] == 0 {
                queue.push_back(w);
            }
        }
    }
    rank
}
