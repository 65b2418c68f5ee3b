//! CPU references of the reductions.

/// findIndex (chapter 10): the first index whose value is ≥ `threshold`, or `values.len()`.
pub fn find_index(values: &[f32], threshold: f32) -> usize {
    values.iter().position(|&v| v >= threshold).unwrap_or(values.len())
}
