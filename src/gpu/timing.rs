//! GPU time per labelled pass: timestamp queries where the adapter has them, otherwise the wall
//! clock around each submission (and the report says which).
//!
//! Resolving and copying timestamps in one encoder can read zeros on Vulkan (wgpu #6406), so the
//! copy to the host goes in a submission of its own ([`read_back`]).

use super::buffers::read_back;
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
    /// Host clock from submit to completion: includes submission overhead and idle gaps.
    WallClock,
}

/// How a GPU render is timed (`--timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Timing {
    /// A timestamp pair around every pass (where the adapter has timestamps): time per label,
    /// at the cost of a host wait whenever the query set fills (every 2048 passes).
    #[default]
    Passes,
    /// No timestamps: the host clock from each submission to its completion, under the label
    /// `frame`, and no waits beyond the method's own. Passes are still counted per label. The
    /// difference from `passes` is what the per-pass instrument costs.
    Frame,
}

/// What a GPU render measures besides its image: SIMD-efficiency counters (`--instrument`) and
/// how passes are timed (`--timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Measure {
    pub instrument: bool,
    pub timing: Timing,
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
    pub passes: BTreeMap<&'static str, PassTime>,
    /// Seconds per bounce (index) for passes that run once per bounce.
    pub per_bounce: BTreeMap<&'static str, Vec<f64>>,
}

impl Timings {
    pub fn total_seconds(&self) -> f64 {
        self.passes.values().map(|p| p.seconds).sum()
    }
}

/// Most passes between two reads: wgpu caps a query set at 4096 queries.
pub const MAX_PASSES_PER_BATCH: u32 = 2048;

pub struct GpuTimer {
    timing: Timing,
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    labels: Vec<(&'static str, Option<u32>)>,
    timings: Timings,
    submitted_at: Option<Instant>,
}

impl GpuTimer {
    pub fn new(ctx: &GpuContext, timing: Timing, memory: &mut MemoryLedger) -> Self {
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
            // The query set holds one 8-byte timestamp per query, as the resolve buffer.
            memory.add(MemoryCategory::Instrumentation, 2 * resolve.size());
            (set, resolve)
        });
        let source = if queries.is_some() { TimeSource::Timestamps } else { TimeSource::WallClock };
        Self {
            timing,
            queries,
            labels: Vec::new(),
            timings: Timings { source, passes: BTreeMap::new(), per_bounce: BTreeMap::new() },
            submitted_at: None,
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
        self.queries.as_ref().map(|(set, _)| wgpu::ComputePassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        })
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
        if let Some((set, buf)) = &self.queries {
            if !self.labels.is_empty() {
                encoder.resolve_query_set(set, 0..2 * self.labels.len() as u32, buf, 0);
            }
        }
        ctx.queue.submit([encoder.finish()]);
        self.submitted_at = Some(Instant::now());
        self.finish_batch(ctx)
    }

    /// Waits for the batch and adds its pass times.
    fn finish_batch(&mut self, ctx: &GpuContext) -> Result<()> {
        ctx.wait()?;
        let labels = std::mem::take(&mut self.labels);
        match &self.queries {
            Some((_, buf)) if !labels.is_empty() => {
                let ticks: Vec<u64> = read_back(ctx, buf, labels.len() as u64 * 16)?;
                let ns_per_tick = ctx.queue.get_timestamp_period() as f64;
                for (i, &(label, bounce)) in labels.iter().enumerate() {
                    let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * ns_per_tick * 1e-9;
                    self.add(label, bounce, dt);
                }
            }
            _ if self.timing == Timing::Frame => {
                // The batch's time as a whole; the passes only counted.
                let dt = self.submitted_at.take().map_or(0.0, |t| t.elapsed().as_secs_f64());
                for &(label, bounce) in &labels {
                    self.add(label, bounce, 0.0);
                }
                self.add(FRAME_LABEL, None, dt);
            }
            _ => {
                // Wall clock: the batch's time is split evenly over its passes.
                let dt = self.submitted_at.take().map_or(0.0, |t| t.elapsed().as_secs_f64());
                for &(label, bounce) in &labels {
                    self.add(label, bounce, dt / labels.len() as f64);
                }
            }
        }
        Ok(())
    }

    fn add(&mut self, label: &'static str, bounce: Option<u32>, seconds: f64) {
        let e = self.timings.passes.entry(label).or_default();
        e.seconds += seconds;
        e.passes += 1;
        if let Some(b) = bounce {
            let v = self.timings.per_bounce.entry(label).or_default();
            if v.len() <= b as usize {
                v.resize(b as usize + 1, 0.0);
            }
            v[b as usize] += seconds;
        }
    }

    pub fn into_timings(self) -> Timings {
        self.timings
    }
}
