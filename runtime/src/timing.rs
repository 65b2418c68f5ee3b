//! The GPU's own clock around compute passes: two timestamp queries a pass, each pair owned by
//! a stage (an index of the caller's: a pipeline stage, a chain's step), resolved in the
//! recording that ran them and read back after it; query sets are added when a recording has
//! more passes than they hold, so every pass of every recording is timed.
//! The executor times every kernel of a frame with it, [`crate::Program::dispatch`] one pass.

use std::time::Duration;

use crate::Gpu;

/// The timestamp queries of one recording, in query sets of a fixed size (a new one when a
/// recording has more passes than the sets so far hold; kept for the next recordings), and the
/// stage each pair belongs to.
pub(crate) struct Timing {
    chunks: Vec<Chunk>,
    /// Queries per set (two a pass).
    chunk_queries: u32,
    used: u32,
    period_ns: f32,
    owners: Vec<usize>,
}

/// One query set and the buffer it resolves into.
struct Chunk {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
}

impl Chunk {
    fn new(gpu: &Gpu, count: u32) -> Chunk {
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let resolved = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass timestamps"),
            size: count as u64 * 8,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Chunk { queries, resolved }
    }
}

impl Timing {
    /// Timestamps for any number of passes, in query sets of `passes_per_set` passes; `None`
    /// unless `gpu` has timestamp queries (a [`Gpu::with_timestamps`]).
    pub fn new(gpu: &Gpu, passes_per_set: u32) -> Option<Timing> {
        if !gpu.times_on_device() {
            return None;
        }
        let chunk_queries = (2 * passes_per_set).clamp(2, wgpu::QUERY_SET_MAX_QUERIES);
        let period_ns = gpu.queue.get_timestamp_period();
        Some(Timing { chunks: Vec::new(), chunk_queries, used: 0, period_ns, owners: Vec::new() })
    }

    /// The writes of the next pass, owned by `stage`.
    pub fn next(&mut self, gpu: &Gpu, stage: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        let (chunk, at) = (self.used / self.chunk_queries, self.used % self.chunk_queries);
        if chunk as usize == self.chunks.len() {
            self.chunks.push(Chunk::new(gpu, self.chunk_queries));
        }
        self.used += 2;
        self.owners.push(stage);
        wgpu::ComputePassTimestampWrites {
            query_set: &self.chunks[chunk as usize].queries,
            beginning_of_pass_write_index: Some(at),
            end_of_pass_write_index: Some(at + 1),
        }
    }

    /// The sets this recording used, each with the number of its queries used.
    fn used_chunks(&self) -> impl Iterator<Item = (&Chunk, u32)> {
        let full = self.chunk_queries;
        self.chunks.iter().enumerate().map_while(move |(k, chunk)| {
            let before = k as u32 * full;
            (before < self.used).then(|| (chunk, (self.used - before).min(full)))
        })
    }

    /// Resolves the recording's timestamps (at its end, before it is submitted).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        for (chunk, used) in self.used_chunks() {
            encoder.resolve_query_set(&chunk.queries, 0..used, &chunk.resolved, 0);
        }
    }

    /// The bytes the recording's timestamps take ([`Timing::copy_into`]).
    pub fn bytes(&self) -> u64 {
        self.used as u64 * 8
    }

    /// Resolves the recording's timestamps and copies them into `staging` at `offset` (at its
    /// end, before it is submitted): they come back with the recording's other reads, in its
    /// submission and its one mapping.
    pub fn copy_into(&self, encoder: &mut wgpu::CommandEncoder, staging: &wgpu::Buffer, mut offset: u64) {
        self.resolve(encoder);
        for (chunk, used) in self.used_chunks() {
            encoder.copy_buffer_to_buffer(&chunk.resolved, 0, staging, offset, used as u64 * 8);
            offset += used as u64 * 8;
        }
    }

    /// The time each timed pass took, by stage, once the recording ran; the sets are then
    /// free for the next recording.
    pub fn take(&mut self, gpu: &Gpu) -> Result<Vec<(usize, Duration)>, String> {
        let mut ticks: Vec<u64> = Vec::with_capacity(self.used as usize);
        for (chunk, used) in self.used_chunks() {
            let bytes = gpu.download(&chunk.resolved, used as u64 * 8)?;
            ticks.extend_from_slice(bytemuck::cast_slice(&bytes));
        }
        let owners = self.end_recording();
        Ok(self.times(&owners, &ticks))
    }

    /// The stage of each pass timed in the recording, which ends: the sets are free for the
    /// next recording (the queue runs it after this one's copies of them).
    pub fn end_recording(&mut self) -> Vec<usize> {
        self.used = 0;
        std::mem::take(&mut self.owners)
    }

    /// The time each pass of a recording took, by stage, from the stages of its passes
    /// ([`Timing::end_recording`]) and its `ticks` (as copied by [`Timing::copy_into`]).
    pub fn times(&self, owners: &[usize], ticks: &[u64]) -> Vec<(usize, Duration)> {
        let ns = |k: usize| ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * self.period_ns as f64;
        owners.iter().enumerate().map(|(k, &stage)| (stage, Duration::from_nanos(ns(k) as u64))).collect()
    }
}
