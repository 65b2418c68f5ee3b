//! Spelling: how far a written name is from the names that exist (Levenshtein distance), and
//! the closest one, for "did you mean" messages and the fixes that correct a typo.

/// The number of single-character insertions, deletions and substitutions from `a` to `b`.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let current = row[j + 1];
            row[j + 1] = (current + 1).min(row[j] + 1).min(previous + usize::from(ca != b[j]));
            previous = current;
        }
    }
    row[b.len()]
}

/// The most a name may be misspelt to count as a typo of another: 2 edits, or a quarter of
/// its length for long names.
pub fn typo_distance(written: &str) -> usize {
    2.max(written.chars().count() / 4)
}

/// The candidate closest to `written` within [`typo_distance`] (the first of equally close
/// ones), other than `written` itself.
pub fn closest<'a>(written: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let most = typo_distance(written);
    let length = written.chars().count();
    candidates
        .into_iter()
        .filter(|c| *c != written && c.chars().count().abs_diff(length) <= most)
        .map(|c| (edit_distance(written, c), c))
        .filter(|(d, _)| *d <= most)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    #[test]
    fn typos_and_their_closest_names() {
        assert_eq!(super::edit_distance("kitten", "sitting"), 3);
        assert_eq!(super::closest("finsh", ["work", "finish", "f"]), Some("finish"));
        assert_eq!(super::closest("process", ["init", "cleanup"]), None);
        assert_eq!(super::closest("same", ["same"]), None);
    }
}
