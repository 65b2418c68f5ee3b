//! What a component keeps for each frame from its `process` to its `finish_frame` (the reads
//! it asked for, what goes with them): kept by the frame's recording, as frames overlap on a
//! GPU and frame n+1's `process` comes before frame n's `finish_frame`.

use std::collections::VecDeque;

use super::{Executor, Reads};

/// A `T` for each frame recorded and not yet finished, oldest first.
pub struct PerFrame<T>(VecDeque<(u64, T)>);

impl<T> Default for PerFrame<T> {
    fn default() -> Self {
        PerFrame(VecDeque::new())
    }
}

impl<T: Default> PerFrame<T> {
    /// The frame `device` records now: its `T` (made when it has none yet).
    pub fn now(&mut self, device: &Executor) -> &mut T {
        let recording = device.recording();
        if self.0.back().is_none_or(|(at, _)| *at != recording) {
            self.0.push_back((recording, T::default()));
        }
        &mut self.0.back_mut().expect("pushed above").1
    }

    /// The `T` of the frame `reads` came back for (none kept: `T::default()`); a frame before
    /// it that never finished (its stage failed) is dropped with it.
    pub fn take(&mut self, reads: &Reads) -> T {
        while self.0.front().is_some_and(|(at, _)| *at < reads.recording()) {
            self.0.pop_front();
        }
        match self.0.front() {
            Some((at, _)) if *at == reads.recording() => self.0.pop_front().expect("checked").1,
            _ => T::default(),
        }
    }
}
