//! A wrapped column's empty stretches squeezed: the ranks of one column came from a layout of
//! all ranks, so the column may hold stretches across it that none of its boxes, labels or
//! edges use (its boxes' places were aligned with ranks now in other columns). Each such
//! stretch wider than a gap is narrowed to the gap, in the same order, so nothing moves past
//! anything else: no crossing appears or goes, no two things come closer than they were or
//! than the gap.

/// The occupied stretches of a column (start, end), sorted and merged, each with how much
/// empty room before it was taken out.
pub(super) struct Squeeze {
    blocks: Vec<(f64, f64, f64)>,
    gap: f64,
}

impl Squeeze {
    /// The stretches `spans` occupy, the empty ones between them narrowed to `gap`.
    pub(super) fn new(mut spans: Vec<(f64, f64)>, gap: f64) -> Squeeze {
        spans.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut blocks: Vec<(f64, f64, f64)> = Vec::with_capacity(spans.len());
        for (start, end) in spans {
            match blocks.last_mut() {
                Some(last) if start <= last.1 + gap => last.1 = last.1.max(end),
                Some(&mut (_, last_end, removed)) => blocks.push((start, end, removed + (start - last_end - gap))),
                None => blocks.push((start, end, 0.0)),
            }
        }
        Squeeze { blocks, gap }
    }

    /// Where `x` goes: moved towards the column's start by the room taken out before it (a
    /// point in a narrowed stretch keeps its distance from the stretch's start, up to the gap).
    pub(super) fn at(&self, x: f64) -> f64 {
        let i = self.blocks.partition_point(|b| b.0 <= x);
        let Some(&(_, end, removed)) = i.checked_sub(1).map(|i| &self.blocks[i]) else { return x };
        if x <= end {
            return x - removed;
        }
        let next_removed = self.blocks.get(i).map_or(removed, |b| b.2);
        x - removed - ((x - end - self.gap).max(0.0)).min(next_removed - removed)
    }

    /// Where the occupied stretches start, and how wide they are together with the gaps left.
    pub(super) fn extent(&self) -> Option<(f64, f64)> {
        let (first, last) = (self.blocks.first()?, self.blocks.last()?);
        Some((first.0, last.1 - last.2 - first.0))
    }
}

#[cfg(test)]
mod tests {
    use super::Squeeze;

    #[test]
    fn wide_empty_stretches_narrow_to_the_gap_and_nothing_changes_order() {
        let squeeze =
            Squeeze::new(vec![(0.0, 10.0), (5.0, 20.0), (100.0, 110.0), (125.0, 130.0), (400.0, 400.0)], 20.0);
        assert_eq!(squeeze.extent(), Some((0.0, 20.0 + 20.0 + 10.0 + 15.0 + 5.0 + 20.0)));
        assert_eq!(squeeze.at(7.0), 7.0);
        assert_eq!(squeeze.at(100.0), 40.0);
        assert_eq!(squeeze.at(127.0), 67.0, "a stretch narrower than the gap is kept");
        assert_eq!(squeeze.at(400.0), 90.0);
        // Inside a narrowed stretch: near its start as it was, then held at the gap.
        assert_eq!(squeeze.at(25.0), 25.0);
        assert_eq!(squeeze.at(90.0), 40.0);
        let xs = [-5.0, 0.0, 15.0, 30.0, 60.0, 99.0, 100.0, 105.0, 118.0, 126.0, 200.0, 399.0, 400.0, 500.0];
        assert!(xs.windows(2).all(|w| squeeze.at(w[0]) <= squeeze.at(w[1])));
    }
}
