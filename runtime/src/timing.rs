//! The GPU's own clock around compute passes: two timestamp queries a pass, each pair owned by
//! a stage (an index of the caller's: a pipeline stage, a chain's step), resolved in the
//! recording that ran them and read back after it; the set grows when a recording needs more.
//! The executor times every kernel of a frame with it, [`crate::Program::dispatch`] one pass.

use std::time::Duration;

use crate::Gpu;

/// The timestamp queries of one recording and the stage each pair belongs to.
pub(crate) struct Timing {
    queries: wgpu::QuerySet,
    capacity: u32,
    used: u32,
    resolved: wgpu::Buffer,
    period_ns: f32,
    owners: Vec<usize>,
}

impl Timing {
    /// Timestamps for `capacity / 2` passes; `None` unless `gpu` has timestamp queries (a
    /// [`Gpu::with_timestamps`]).
    pub fn new(gpu: &Gpu, capacity: u32) -> Option<Timing> {
        if !gpu.times_on_device() {
            return None;
        }
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        let resolved = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass timestamps"),
            size: capacity as u64 * 8,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let period_ns = gpu.queue.get_timestamp_period();
        Some(Timing { queries, capacity, used: 0, resolved, period_ns, owners: Vec::new() })
    }

    /// The writes of the next pass, owned by `stage`; `None` when the set is full for this
    /// recording (it grows for the next).
    pub fn next(&mut self, stage: usize) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        if self.used + 2 > self.capacity {
            return None;
        }
        let at = self.used;
        self.used += 2;
        self.owners.push(stage);
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(at),
            end_of_pass_write_index: Some(at + 1),
        })
    }

    /// Resolves the recording's timestamps (at its end, before it is submitted).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if self.used > 0 {
            encoder.resolve_query_set(&self.queries, 0..self.used, &self.resolved, 0);
        }
    }

    /// The time each timed pass took, by stage, once the recording ran; the set is then empty
    /// for the next recording (and twice as large if this one filled it).
    pub fn take(&mut self, gpu: &Gpu) -> Result<Vec<(usize, Duration)>, String> {
        if self.used == 0 {
            return Ok(Vec::new());
        }
        let bytes = gpu.download(&self.resolved, self.used as u64 * 8)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let times = self
            .owners
            .iter()
            .enumerate()
            .map(|(k, &stage)| {
                let ns = ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * self.period_ns as f64;
                (stage, Duration::from_nanos(ns as u64))
            })
            .collect();
        let full = self.owners.len() as u32 * 2 >= self.capacity;
        self.used = 0;
        self.owners.clear();
        if full {
            if let Some(grown) = Timing::new(gpu, self.capacity * 2) {
                *self = grown;
            }
        }
        Ok(times)
    }
}
