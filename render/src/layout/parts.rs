//! The connected parts of a graph of boxes (union–find): which boxes a layout can lay out apart
//! from the others, and rank from the top each.

/// Each of `n` boxes' connected part under `edges`, named by its first box.
pub(super) fn connected_parts(n: usize, edges: impl IntoIterator<Item = (usize, usize)>) -> Vec<usize> {
    let mut part: Vec<usize> = (0..n).collect();
    fn find(part: &mut [usize], v: usize) -> usize {
        let mut root = v;
        while part[root] != root {
            root = part[root];
        }
        let mut at = v;
        while part[at] != root {
            (part[at], at) = (root, part[at]);
        }
        root
    }
    for (a, b) in edges {
        let (ra, rb) = (find(&mut part, a), find(&mut part, b));
        // A part's root is its first box.
        part[ra.max(rb)] = ra.min(rb);
    }
    (0..n).map(|v| find(&mut part, v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_box_is_named_by_the_first_box_of_its_part() {
        let parts = connected_parts(6, [(4, 2), (2, 5), (3, 1)]);
        assert_eq!(parts, [0, 1, 2, 1, 2, 2]);
    }
}
