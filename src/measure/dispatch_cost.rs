//! What a dispatch costs by itself (issue 42): a chain of N tiny dispatches recorded the ways
//! the wavefront could record its passes, timed on the GPU (a timestamp before the chain's first
//! dispatch and after its last) and on the host (recording, submission, the whole round trip).
//! The floor that the wavefront's time between passes is measured against.
//!
//! Variants: one compute pass per dispatch (as `Stage::record` records every wavefront pass) or
//! all dispatches in one pass; direct or indirect arguments; the chain's buffer bound read-write
//! (each dispatch depends on the one before it: wgpu puts a barrier before each) or read-only
//! (nothing to order: no barrier). The variants take turns, repetition by repetition, after one
//! untimed round, as the experiment runner's GPU variants do.

use std::time::Instant;

use anyhow::{bail, Result};
use serde::Serialize;

use crate::gpu::buffers::{storage_entry, Staging};
use crate::gpu::context::{AdapterSummary, GpuContext};
use crate::gpu::label;
use crate::gpu::timestamp_pair::{TimestampPair, END, START};

/// How a variant records its chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Variant {
    pub name: &'static str,
    /// All dispatches in one compute pass, else one pass each.
    pub one_pass: bool,
    pub indirect: bool,
    /// The chain's buffer bound read-only (`chain_read`), else read-write (`chain_link`).
    pub read_only: bool,
}

/// Every variant, today's recording first.
pub const VARIANTS: [Variant; 6] = [
    Variant { name: "pass-per-dispatch", one_pass: false, indirect: false, read_only: false },
    Variant { name: "pass-per-dispatch-indirect", one_pass: false, indirect: true, read_only: false },
    Variant { name: "pass-per-dispatch-read-only", one_pass: false, indirect: false, read_only: true },
    Variant { name: "one-pass", one_pass: true, indirect: false, read_only: false },
    Variant { name: "one-pass-indirect", one_pass: true, indirect: true, read_only: false },
    Variant { name: "one-pass-read-only", one_pass: true, indirect: false, read_only: true },
];

/// Median, min and max of a variant's repetitions.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// Of one or more values (`measure::intersect_cost` uses it too).
    pub fn of(values: &[f64]) -> Self {
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        Self { median: crate::stats::median_of_sorted(&v), min: v[0], max: v[v.len() - 1] }
    }
}

/// One variant's measurements, per dispatch, in microseconds.
#[derive(Clone, Debug, Serialize)]
pub struct VariantResult {
    #[serde(flatten)]
    pub variant: Variant,
    pub compute_passes: u32,
    /// GPU time from the first dispatch's start to the last one's end (timestamps), ÷ dispatches;
    /// None without timestamps.
    pub gpu_us_per_dispatch: Option<Spread>,
    /// Host time to record the chain into a command encoder and finish it, ÷ dispatches.
    pub record_us_per_dispatch: Spread,
    /// Host time of `queue.submit`, whole (not per dispatch).
    pub submit_us: Spread,
    /// Host time from the start of recording to the chain's completion, ÷ dispatches.
    pub round_trip_us_per_dispatch: Spread,
    /// The read-write chain's counter ended at N × (repetitions + 1): every dispatch ran, in order
    /// (always true for the read-only chain, which has no counter).
    pub counter_ok: bool,
}

/// The microbenchmark's report (`wavetrace dispatch-cost --json`).
#[derive(Clone, Debug, Serialize)]
pub struct DispatchCostReport {
    pub schema: &'static str,
    pub build: crate::report::Build,
    pub machine: crate::report::Machine,
    pub adapter: AdapterSummary,
    pub dispatches: u32,
    pub repetitions: u32,
    /// GPU times come from timestamps (the adapter has them).
    pub timestamps: bool,
    pub variants: Vec<VariantResult>,
}

pub const DISPATCH_COST_SCHEMA: &str = "wavetrace-dispatch-cost/1";

/// The most dispatches one chain may hold: far more than a frame's passes, and little memory.
pub const MAX_DISPATCHES: u32 = 100_000;

/// Runs every variant's chain of `dispatches` tiny dispatches: one untimed round, then
/// `repetitions` rounds in which the variants take turns.
pub fn measure(ctx: &GpuContext, dispatches: u32, repetitions: u32) -> Result<DispatchCostReport> {
    if !(1..=MAX_DISPATCHES).contains(&dispatches) {
        bail!("--dispatches must be in 1..={MAX_DISPATCHES}, got {dispatches}");
    }
    if repetitions == 0 {
        bail!("--repetitions must be at least 1");
    }
    let bench = Bench::new(ctx)?;
    let mut samples: Vec<Vec<Sample>> = vec![Vec::new(); VARIANTS.len()];
    for round in 0..=repetitions {
        for (i, v) in VARIANTS.iter().enumerate() {
            let s = bench.run(ctx, v, dispatches)?;
            if round > 0 {
                samples[i].push(s);
            }
        }
    }
    let counter: Vec<u32> = bench.counter(ctx)?;
    let linked = VARIANTS.iter().filter(|v| !v.read_only).count() as u64;
    let expected = u64::from(dispatches) * u64::from(repetitions + 1) * linked;
    let per = |x: f64| 1e6 * x / f64::from(dispatches);
    let variants = VARIANTS
        .iter()
        .zip(&samples)
        .map(|(v, s)| {
            let gpu: Option<Vec<f64>> = s.iter().map(|x| x.gpu_seconds.map(per)).collect();
            VariantResult {
                variant: *v,
                compute_passes: if v.one_pass { 1 } else { dispatches },
                gpu_us_per_dispatch: gpu.map(|g| Spread::of(&g)),
                record_us_per_dispatch: Spread::of(
                    &s.iter().map(|x| per(x.record_seconds)).collect::<Vec<_>>(),
                ),
                submit_us: Spread::of(&s.iter().map(|x| 1e6 * x.submit_seconds).collect::<Vec<_>>()),
                round_trip_us_per_dispatch: Spread::of(
                    &s.iter().map(|x| per(x.round_trip_seconds)).collect::<Vec<_>>(),
                ),
                counter_ok: v.read_only || u64::from(counter[0]) == expected,
            }
        })
        .collect();
    Ok(DispatchCostReport {
        schema: DISPATCH_COST_SCHEMA,
        build: crate::report::Build::this(),
        machine: crate::report::Machine::this(),
        adapter: ctx.summary.clone(),
        dispatches,
        repetitions,
        timestamps: bench.queries.is_some(),
        variants,
    })
}

#[derive(Clone, Copy, Debug)]
struct Sample {
    gpu_seconds: Option<f64>,
    record_seconds: f64,
    submit_seconds: f64,
    round_trip_seconds: f64,
}

/// The pipelines, buffers and queries every chain shares.
struct Bench {
    link: wgpu::ComputePipeline,
    read: wgpu::ComputePipeline,
    link_group: wgpu::BindGroup,
    read_group: wgpu::BindGroup,
    counter: wgpu::Buffer,
    /// Indirect arguments: one workgroup.
    args: wgpu::Buffer,
    queries: Option<TimestampPair>,
    counter_staging: Staging,
}

impl Bench {
    fn new(ctx: &GpuContext) -> Result<Self> {
        let module = ctx.shader("dispatch_chain", crate::gpu::shaders::DISPATCH_CHAIN, Default::default())?;
        let link_layout = ctx.bind_group_layout("dispatch chain (read-write)", &[storage_entry(0, false)]);
        let read_layout = ctx.bind_group_layout("dispatch chain (read-only)", &[storage_entry(1, true)]);
        let link = ctx.compute_pipeline(label::CHAIN_LINK, &module, &[&link_layout], &[])?;
        let read = ctx.compute_pipeline(label::CHAIN_READ, &module, &[&read_layout], &[])?;
        let buffer = |label: &str, usage: wgpu::BufferUsages, data: &[u32]| {
            use wgpu::util::DeviceExt;
            ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(data),
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let counter = buffer("dispatch chain counter", storage, &[0; 4]);
        let input = buffer("dispatch chain input", wgpu::BufferUsages::STORAGE, &[0; 4]);
        let args = buffer("dispatch chain arguments", wgpu::BufferUsages::INDIRECT, &[1, 1, 1]);
        let group = |layout: &wgpu::BindGroupLayout, binding: u32, buffer: &wgpu::Buffer| {
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("dispatch chain"),
                layout,
                entries: &[wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }],
            })
        };
        let link_group = group(&link_layout, 0, &counter);
        let read_group = group(&read_layout, 1, &input);
        let queries = TimestampPair::new(ctx, "dispatch chain timestamps");
        let counter_staging = Staging::new(ctx, "dispatch chain counter read-back", 16);
        ctx.check()?;
        Ok(Self { link, read, link_group, read_group, counter, args, queries, counter_staging })
    }

    /// One chain of `n` dispatches recorded as `v` says, submitted and waited for.
    fn run(&self, ctx: &GpuContext, v: &Variant, n: u32) -> Result<Sample> {
        let (pipeline, group) =
            if v.read_only { (&self.read, &self.read_group) } else { (&self.link, &self.link_group) };
        let start = Instant::now();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        // The first timestamp before the first dispatch, the second after the last.
        let writes = |first: bool, last: bool| {
            self.queries.as_ref().and_then(|q| q.writes(first.then_some(START), last.then_some(END)))
        };
        let dispatch = |pass: &mut wgpu::ComputePass<'_>| {
            if v.indirect {
                pass.dispatch_workgroups_indirect(&self.args, 0);
            } else {
                pass.dispatch_workgroups(1, 1, 1);
            }
        };
        let label = if v.read_only { label::CHAIN_READ } else { label::CHAIN_LINK };
        if v.one_pass {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: writes(true, true),
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            for _ in 0..n {
                dispatch(&mut pass);
            }
        } else {
            for i in 0..n {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: writes(i == 0, i + 1 == n),
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                dispatch(&mut pass);
            }
        }
        if let Some(q) = &self.queries {
            q.resolve(&mut encoder);
        }
        let commands = encoder.finish();
        let recorded = Instant::now();
        ctx.queue.submit([commands]);
        let submitted = Instant::now();
        ctx.wait()?;
        let done = Instant::now();
        let gpu_seconds = match &self.queries {
            Some(q) => q.seconds(ctx)?,
            None => None,
        };
        Ok(Sample {
            gpu_seconds,
            record_seconds: recorded.duration_since(start).as_secs_f64(),
            submit_seconds: submitted.duration_since(recorded).as_secs_f64(),
            round_trip_seconds: done.duration_since(start).as_secs_f64(),
        })
    }

    /// The read-write chain's counter.
    fn counter(&self, ctx: &GpuContext) -> Result<Vec<u32>> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        self.counter_staging.copy(&mut enc, &self.counter, 16);
        ctx.queue.submit([enc.finish()]);
        self.counter_staging.read(ctx, 16)
    }
}

impl DispatchCostReport {
    /// The table `wavetrace dispatch-cost` prints.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut t = format!(
            "{} ({}), a chain of {} dispatches, median [min–max] of {} repetitions, µs per dispatch\n",
            self.adapter.name, self.adapter.backend, self.dispatches, self.repetitions
        );
        let _ = writeln!(
            t,
            "{:<30} {:>8} {:>26} {:>10} {:>12} {:>10}  counter",
            "variant", "passes", "GPU", "record", "round trip", "submit µs"
        );
        for v in &self.variants {
            let gpu = v.gpu_us_per_dispatch.map_or("– (no timestamps)".to_string(), |g| {
                format!("{:.3} [{:.3}–{:.3}]", g.median, g.min, g.max)
            });
            let _ = writeln!(
                t,
                "{:<30} {:>8} {:>26} {:>10.3} {:>12.3} {:>10.1}  {}",
                v.variant.name,
                v.compute_passes,
                gpu,
                v.record_us_per_dispatch.median,
                v.round_trip_us_per_dispatch.median,
                v.submit_us.median,
                if v.counter_ok { "ok" } else { "WRONG" }
            );
        }
        t
    }
}
