//! GPU time per labelled pass: timestamp queries where the adapter has them, otherwise the wall
//! clock around each submission under the label `frame` (per-pass times are then unavailable,
//! never invented). Beside it, the frame time: the wall clock from the first submission to the
//! last completion, which includes what the sum of passes leaves out — the GPU idle while the
//! host reads counters back and decides, between submissions.
//!
//! Resolving and copying timestamps in one encoder can read zeros on Vulkan (wgpu #6406), so the
//! copy to the host goes in a submission of its own, into a staging buffer reused by every batch.

pub use crate::options::Timing;

use super::buffers::Staging;
use super::context::GpuContext;
use super::memory::{MemoryCategory, MemoryLedger};
use anyhow::Result;
use std::collections::BTreeMap;
use std::time::Instant;

/// Where GPU times come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeSource {
    /// Timestamp queries at the start and end of every pass.
    Timestamps,
    /// Host clock from submit to completion, per submission (label `frame`): includes
    /// submission overhead and idle gaps; no time per pass. Also where timestamps read as zeros
    /// (macOS 26 Metal, wgpu #9414): they count as missing.
    WallClock,
}

/// What a GPU render measures besides its image, and how: SIMD-efficiency counters
/// (`--instrument`), how passes are timed (`--timing`), the shaders' runtime checks and
/// specialization, and the preheat before the frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measure {
    pub instrument: bool,
    pub timing: Timing,
    /// Shaders compiled with wgpu's runtime checks or without (`--shader-checks`).
    pub shader_checks: super::shader_checks::ShaderChecks,
    /// Shaders compiled for the scene's kinds or for every kind (`--specialize`).
    pub specialize: crate::options::Specialize,
    /// Seconds of busy work before the first submission (`gpu::preheat`; 0: none).
    pub preheat_seconds: f64,
}

/// The label that carries the whole time of a `--timing frame` render.
pub const FRAME_LABEL: &str = "frame";

/// Total GPU time and pass count of one label.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PassTime {
    pub seconds: f64,
    pub passes: u64,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Timings {
    pub source: TimeSource,
    /// Wall-clock seconds from the first submission to the last completion: the GPU's work and
    /// its idle time between submissions (host read-backs and decisions) alike.
    pub frame_seconds: f64,
    /// Wall-clock seconds within the frame between a submission's completion and the next
    /// submission: the GPU certainly idle while the host reads back and records. The rest of
    /// the frame outside the passes is the GPU's own time between passes (launches, barriers).
    pub host_gap_seconds: f64,
    /// Submissions in the frame.
    pub submissions: u64,
    /// Times the host waited for the GPU (to read counters or timestamps back before it records
    /// more, or at the end): all but the last are blocking waits inside the frame, what issue
    /// 42's host loop that never waits is to bring to zero. Fewer than `submissions` where the
    /// host submits without waiting (waves without per-pass timestamps).
    pub waits: u64,
    /// Seconds of preheat before the first submission (not part of the frame; `gpu::preheat`).
    pub preheat_seconds: f64,
    pub passes: BTreeMap<&'static str, PassTime>,
    /// Seconds per bounce (index) for passes that run once per bounce.
    pub per_bounce: BTreeMap<&'static str, Vec<f64>>,
}

impl Timings {
    /// Nothing timed yet, from `source`.
    pub fn new(source: TimeSource) -> Self {
        Self {
            source,
            frame_seconds: 0.0,
            host_gap_seconds: 0.0,
            submissions: 0,
            waits: 0,
            preheat_seconds: 0.0,
            passes: BTreeMap::new(),
            per_bounce: BTreeMap::new(),
        }
    }

    /// The sum of pass times (timestamps), or of submission times (wall clock).
    pub fn total_seconds(&self) -> f64 {
        self.passes.values().map(|p| p.seconds).sum()
    }

    /// Whether each pass has its own measured time (timestamps that were delivered).
    pub fn per_pass(&self) -> bool {
        self.source == TimeSource::Timestamps
    }

    /// Adds a finished batch: its passes `labels`, their timestamp pairs `ticks` (None without
    /// timestamps) and the batch's wall-clock seconds. With timestamps each pass gets its own
    /// time. Without, or once a batch's timestamps all read zero (the adapter claims
    /// timestamps it does not deliver), the passes are only counted and the batch's time goes
    /// to `frame` whole: a pass is never given a share it was not measured to take. Returns
    /// true when this batch found the timestamps to be zeros (the source becomes wall clock,
    /// and the passes timed before lose their times to `frame`).
    pub fn add_batch(
        &mut self,
        labels: &[(&'static str, Option<u32>)],
        ticks: Option<&[u64]>,
        ns_per_tick: f64,
        batch_seconds: f64,
    ) -> bool {
        let mut found_zeros = false;
        match ticks {
            // A batch with no pass (only copies or clears): nothing to time per pass, and its
            // time is in the frame time already.
            None if self.source == TimeSource::Timestamps => return false,
            Some(ticks) if ticks.iter().any(|&t| t != 0) && self.source == TimeSource::Timestamps => {
                for (i, &(label, bounce)) in labels.iter().enumerate() {
                    let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * ns_per_tick * 1e-9;
                    self.add(label, bounce, dt);
                }
                return false;
            }
            Some(_) if self.source == TimeSource::Timestamps => {
                found_zeros = true;
                self.source = TimeSource::WallClock;
                let timed: f64 = self.passes.values().map(|p| p.seconds).sum();
                for p in self.passes.values_mut() {
                    p.seconds = 0.0;
                }
                self.per_bounce.clear();
                if timed > 0.0 {
                    self.passes.entry(FRAME_LABEL).or_default().seconds += timed;
                }
            }
            _ => {}
        }
        // Counted only; no time per bounce either.
        for &(label, _) in labels {
            self.add(label, None, 0.0);
        }
        self.add(FRAME_LABEL, None, batch_seconds);
        found_zeros
    }

    fn add(&mut self, label: &'static str, bounce: Option<u32>, seconds: f64) {
        let e = self.passes.entry(label).or_default();
        e.seconds += seconds;
        e.passes += 1;
        if let Some(b) = bounce {
            let v = self.per_bounce.entry(label).or_default();
            if v.len() <= b as usize {
                v.resize(b as usize + 1, 0.0);
            }
            v[b as usize] += seconds;
        }
    }
}

/// Most passes between two reads: wgpu caps a query set at 4096 queries.
pub const MAX_PASSES_PER_BATCH: u32 = 2048;

pub struct GpuTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, Staging)>,
    labels: Vec<(&'static str, Option<u32>)>,
    timings: Timings,
    submitted_at: Option<Instant>,
    first_submitted: Option<Instant>,
    last_done: Option<Instant>,
    /// Seconds of preheat still to do before the first submission.
    preheat: f64,
}

impl GpuTimer {
    /// `preheat`: seconds of busy work before the first submission (`gpu::preheat`).
    pub fn new(ctx: &GpuContext, timing: Timing, preheat: f64, memory: &mut MemoryLedger) -> Self {
        let queries = (ctx.summary.timestamps && timing == Timing::Passes).then(|| {
            let count = 2 * MAX_PASSES_PER_BATCH;
            let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            });
            let resolve = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: count as u64 * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let staging = Staging::new(ctx, "timestamp read-back", resolve.size());
            // The query set holds one 8-byte timestamp per query, as do the resolve and staging
            // buffers.
            memory.add(MemoryCategory::Instrumentation, 3 * resolve.size());
            (set, resolve, staging)
        });
        let source = if queries.is_some() { TimeSource::Timestamps } else { TimeSource::WallClock };
        Self {
            queries,
            labels: Vec::new(),
            timings: Timings::new(source),
            submitted_at: None,
            first_submitted: None,
            last_done: None,
            preheat: super::preheat::on(ctx, preheat),
        }
    }

    /// Timestamp writes for the next pass, labelled `label`. At most [`MAX_PASSES_PER_BATCH`]
    /// passes between [`GpuTimer::finish_batch`] calls.
    pub fn pass(&mut self, label: &'static str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.pass_at(label, None)
    }

    /// Like [`GpuTimer::pass`], also attributing the time to `bounce`.
    pub fn pass_at(
        &mut self,
        label: &'static str,
        bounce: Option<u32>,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        assert!(!self.is_full(), "too many passes in one timing batch");
        let i = self.labels.len() as u32;
        self.labels.push((label, bounce));
        self.queries.as_ref().map(|(set, _, _)| wgpu::ComputePassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        })
    }

    /// Whether passes get timestamps (each then needs a compute pass of its own).
    pub fn times_passes(&self) -> bool {
        self.queries.is_some()
    }

    /// True when the batch must be finished before another pass is recorded.
    pub fn is_full(&self) -> bool {
        self.remaining() == 0
    }

    /// Passes that can still be recorded in this batch (no limit without timestamp queries).
    pub fn remaining(&self) -> usize {
        if self.queries.is_none() {
            return usize::MAX;
        }
        MAX_PASSES_PER_BATCH as usize - self.labels.len()
    }

    /// Ends a batch: records the resolve of its queries as the encoder's last command, submits
    /// the encoder, waits for it and adds its pass times. The one submit loop of every GPU method.
    pub fn submit_batch(&mut self, ctx: &GpuContext, mut encoder: wgpu::CommandEncoder) -> Result<()> {
        if let Some((set, buf, _)) = &self.queries {
            if !self.labels.is_empty() {
                encoder.resolve_query_set(set, 0..2 * self.labels.len() as u32, buf, 0);
            }
        }
        self.submit_only(ctx, encoder)?;
        self.finish_batch(ctx)
    }

    /// Submits without waiting: the GPU works through it while the host records more, and the
    /// next [`GpuTimer::submit_batch`] waits for both. Only without per-pass timestamps, which
    /// are read back batch by batch.
    pub fn submit(
        &mut self,
        ctx: &GpuContext,
        encoder: wgpu::CommandEncoder,
    ) -> Result<wgpu::SubmissionIndex> {
        assert!(!self.times_passes(), "per-pass timestamps are read back per batch: submit_batch");
        self.submit_only(ctx, encoder)
    }

    fn submit_only(
        &mut self,
        ctx: &GpuContext,
        encoder: wgpu::CommandEncoder,
    ) -> Result<wgpu::SubmissionIndex> {
        if self.first_submitted.is_none() && self.preheat > 0.0 {
            self.timings.preheat_seconds = super::preheat::run(ctx, std::mem::take(&mut self.preheat))?;
        }
        let index = ctx.queue.submit([encoder.finish()]);
        self.timings.submissions += 1;
        let now = Instant::now();
        // The GPU idled from the last wait's end until now (only the first submission after a
        // wait follows one).
        if let Some(done) = self.last_done.take() {
            self.timings.host_gap_seconds += now.duration_since(done).as_secs_f64();
        }
        self.submitted_at.get_or_insert(now);
        self.first_submitted.get_or_insert(now);
        Ok(index)
    }

    /// Counts a blocking wait the method made itself (the regenerating host loop's for a
    /// read-back, nothing newer queued) and starts a host gap: the GPU idles from now until the
    /// next submission. (A wait with newer work queued is no such wait: the GPU stays busy.)
    pub fn note_blocking_wait(&mut self) {
        self.timings.waits += 1;
        self.last_done = Some(Instant::now());
    }

    /// Waits for the batch and adds its pass times.
    fn finish_batch(&mut self, ctx: &GpuContext) -> Result<()> {
        ctx.wait()?;
        self.timings.waits += 1;
        let done = Instant::now();
        self.last_done = Some(done);
        if let Some(first) = self.first_submitted {
            self.timings.frame_seconds = done.duration_since(first).as_secs_f64();
        }
        let batch = self.submitted_at.take().map_or(0.0, |t| done.duration_since(t).as_secs_f64());
        let labels = std::mem::take(&mut self.labels);
        let ticks: Option<Vec<u64>> = match &self.queries {
            Some((_, buf, staging)) if !labels.is_empty() => {
                let size = labels.len() as u64 * 16;
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                staging.copy(&mut enc, buf, size);
                ctx.queue.submit([enc.finish()]);
                Some(staging.read(ctx, size)?)
            }
            _ => None,
        };
        let ns_per_tick = ctx.queue.get_timestamp_period() as f64;
        if self.timings.add_batch(&labels, ticks.as_deref(), ns_per_tick, batch) {
            log::warn!("{}'s timestamps read as zeros: timing on the wall clock", ctx.summary.name);
        }
        Ok(())
    }

    pub fn into_timings(self) -> Timings {
        self.timings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_time_each_pass() {
        let mut t = Timings::new(TimeSource::Timestamps);
        let zeros =
            t.add_batch(&[("intersect", Some(0)), ("shade", Some(0))], Some(&[10, 30, 30, 40]), 1e6, 9.0);
        assert!(!zeros);
        assert_eq!(t.passes["intersect"], PassTime { seconds: 0.02, passes: 1 });
        assert!((t.passes["shade"].seconds - 0.01).abs() < 1e-12);
        assert!(!t.passes.contains_key(FRAME_LABEL));
        assert!(t.per_pass());
        // A batch of copies only (no pass) adds no row: its time is in the frame time.
        assert!(!t.add_batch(&[], None, 1e6, 4.0));
        assert!(!t.passes.contains_key(FRAME_LABEL));
        assert_eq!(t.passes.len(), 2);
    }

    /// Without timestamps no pass is given a share of its batch's time: it goes to `frame`.
    #[test]
    fn the_wall_clock_times_batches_not_passes() {
        let mut t = Timings::new(TimeSource::WallClock);
        t.add_batch(&[("intersect", Some(0)), ("shade", Some(0))], None, 1.0, 0.5);
        t.add_batch(&[("intersect", Some(1))], None, 1.0, 0.25);
        assert_eq!(t.passes["intersect"], PassTime { seconds: 0.0, passes: 2 });
        assert_eq!(t.passes["shade"], PassTime { seconds: 0.0, passes: 1 });
        assert_eq!(t.passes[FRAME_LABEL], PassTime { seconds: 0.75, passes: 2 });
        assert_eq!(t.total_seconds(), 0.75);
        assert!(!t.per_pass());
    }

    /// Timestamps that read as zeros (macOS 26 Metal, wgpu #9414) are missing, not free: the
    /// source becomes the wall clock, earlier pass times move to `frame`.
    #[test]
    fn zero_timestamps_count_as_missing() {
        let mut t = Timings::new(TimeSource::Timestamps);
        assert!(!t.add_batch(&[("intersect", Some(0))], Some(&[0, 1000]), 1.0, 0.5));
        assert!(t.add_batch(&[("intersect", Some(1)), ("shade", Some(1))], Some(&[0, 0, 0, 0]), 1.0, 0.5));
        assert_eq!(t.source, TimeSource::WallClock);
        assert_eq!(t.passes["intersect"], PassTime { seconds: 0.0, passes: 2 });
        assert_eq!(t.passes[FRAME_LABEL].passes, 1);
        assert!((t.passes[FRAME_LABEL].seconds - (1e-6 + 0.5)).abs() < 1e-12);
        assert!(t.per_bounce.is_empty());
        // Later batches stay on the wall clock even if a timestamp reads non-zero.
        assert!(!t.add_batch(&[("intersect", Some(2))], Some(&[5, 9]), 1.0, 0.25));
        assert_eq!(t.passes["intersect"].seconds, 0.0);
    }
}
