//! What this device's memory delivers to a pass that streams 16-byte elements (issue 44, item
//! 1c): the floor under the wavefront's path-state traffic. A pass's modelled bytes over its time
//! (`state_traffic` in reports) is its achieved bandwidth; this is what a copy reaches on the same
//! device. Three ways, taking turns repetition by repetition after one untimed round:
//!
//! - `stream_copy`: a compute pass, each thread copying one element (reads and writes);
//! - `stream_read`: a compute pass, each thread reading one element (reads only);
//! - `buffer_copy`: `copy_buffer_to_buffer`, timed between the end of one timestamped compute
//!   pass and the start of the next (so the time includes the transitions around the copy).
//!
//! Each copy is checked element by element after the last repetition.

use std::time::Instant;

use anyhow::{bail, Result};
use serde::Serialize;

use super::dispatch_cost::Spread;
use crate::gpu::buffers::{read_back, storage_entry};
use crate::gpu::context::{AdapterSummary, GpuContext};
use crate::gpu::label;
use crate::gpu::timestamp_pair::{TimestampPair, END, START};

/// The ways the benchmark moves memory.
pub const WAYS: [&str; 3] = [label::STREAM_COPY, label::STREAM_READ, label::BUFFER_COPY];

/// One way's measurements.
#[derive(Clone, Debug, Serialize)]
pub struct WayResult {
    pub way: &'static str,
    /// Bytes read plus written per repetition.
    pub bytes: u64,
    /// GB/s (10⁹ bytes per second) over GPU time from timestamps; None without timestamps.
    pub gpu_gb_per_s: Option<Spread>,
    /// GB/s over the host's round trip (recording, submission, completion): a lower bound.
    pub round_trip_gb_per_s: Spread,
}

/// The microbenchmark's report (`wavetrace bandwidth --json`).
#[derive(Clone, Debug, Serialize)]
pub struct BandwidthReport {
    pub schema: &'static str,
    pub build: crate::report::Build,
    pub machine: crate::report::Machine,
    pub adapter: AdapterSummary,
    /// Bytes of each buffer (source and destination).
    pub buffer_bytes: u64,
    pub repetitions: u32,
    pub timestamps: bool,
    pub ways: Vec<WayResult>,
    /// Each copying way left the destination holding the source, element for element.
    pub copy_ok: bool,
}

pub const BANDWIDTH_SCHEMA: &str = "wavetrace-bandwidth/1";

const WORKGROUP: u64 = 256;
const ELEMENT: u64 = 16;

/// Measures each way over buffers of `mib` MiB (at most what one storage binding holds here):
/// one untimed round, then `repetitions` rounds in which the ways take turns.
pub fn measure(ctx: &GpuContext, mib: u64, repetitions: u32) -> Result<BandwidthReport> {
    if repetitions == 0 {
        bail!("--repetitions must be at least 1");
    }
    let limit = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size);
    let bytes = mib.saturating_mul(1 << 20);
    if mib == 0 || bytes > limit {
        bail!(
            "--mib must be in 1..={} on {} (its largest storage binding is {}), got {mib}",
            limit >> 20,
            ctx.summary.name,
            crate::gpu::buffers::human_bytes(limit)
        );
    }
    let bench = Bench::new(ctx, bytes)?;
    let mut seconds: Vec<Vec<(Option<f64>, f64)>> = vec![Vec::new(); WAYS.len()];
    for round in 0..=repetitions {
        for (i, way) in WAYS.iter().enumerate() {
            let s = bench.run(ctx, way)?;
            if round > 0 {
                seconds[i].push(s);
            }
        }
    }
    let copy_ok = bench.copied(ctx)?;
    let ways = WAYS
        .iter()
        .zip(&seconds)
        .map(|(&way, s)| {
            let moved = if way == label::STREAM_READ { bytes } else { 2 * bytes };
            let rate = |t: f64| moved as f64 / t * 1e-9;
            let gpu: Option<Vec<f64>> = s.iter().map(|(g, _)| g.map(rate)).collect();
            WayResult {
                way,
                bytes: moved,
                gpu_gb_per_s: gpu.map(|g| Spread::of(&g)),
                round_trip_gb_per_s: Spread::of(&s.iter().map(|(_, w)| rate(*w)).collect::<Vec<_>>()),
            }
        })
        .collect();
    Ok(BandwidthReport {
        schema: BANDWIDTH_SCHEMA,
        build: crate::report::Build::this(),
        machine: crate::report::Machine::this(),
        adapter: ctx.summary.clone(),
        buffer_bytes: bytes,
        repetitions,
        timestamps: bench.queries.is_some(),
        ways,
        copy_ok,
    })
}

struct Bench {
    copy: wgpu::ComputePipeline,
    read: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    src: wgpu::Buffer,
    dst: wgpu::Buffer,
    bytes: u64,
    /// Workgroups in x and y.
    grid: (u32, u32),
    queries: Option<TimestampPair>,
}

/// The source's element i (integers: the copy is checked bit for bit), its w never the value
/// `stream_read` tests for.
fn element(i: u64) -> [u32; 4] {
    [i as u32, (i >> 32) as u32, (i as u32) ^ 0x5555_5555, 1]
}

impl Bench {
    fn new(ctx: &GpuContext, bytes: u64) -> Result<Self> {
        let elements = bytes / ELEMENT;
        let groups = elements.div_ceil(WORKGROUP);
        let max = ctx.summary.max_compute_workgroups_per_dimension as u64;
        let x = groups.min(max);
        let grid = (x as u32, groups.div_ceil(x) as u32);
        let module = ctx.shader("bandwidth", crate::gpu::shaders::BANDWIDTH, Default::default())?;
        let layout = ctx.bind_group_layout("bandwidth", &[storage_entry(0, true), storage_entry(1, false)]);
        let row = [("ROW", (x * WORKGROUP) as f64)];
        let copy = ctx.compute_pipeline(label::STREAM_COPY, &module, &[&layout], &row)?;
        let read = ctx.compute_pipeline(label::STREAM_READ, &module, &[&layout], &row)?;
        let data: Vec<[u32; 4]> = (0..elements).map(element).collect();
        let src = {
            use wgpu::util::DeviceExt;
            ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("bandwidth source"),
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
        };
        let dst = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bandwidth destination"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bandwidth"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: src.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: dst.as_entire_binding() },
            ],
        });
        let queries = TimestampPair::new(ctx, "bandwidth timestamps");
        ctx.check()?;
        Ok(Self { copy, read, group, src, dst, bytes, grid, queries })
    }

    /// One repetition of `way`, submitted and waited for: (GPU seconds, round-trip seconds).
    fn run(&self, ctx: &GpuContext, way: &str) -> Result<(Option<f64>, f64)> {
        let start = Instant::now();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        let writes = |beginning, end| self.queries.as_ref().and_then(|q| q.writes(beginning, end));
        if way == label::BUFFER_COPY {
            // Empty passes around the copy carry its timestamps: the first's end, the second's start.
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label::BUFFER_COPY),
                timestamp_writes: writes(None, Some(START)),
            }));
            encoder.copy_buffer_to_buffer(&self.src, 0, &self.dst, 0, self.bytes);
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label::BUFFER_COPY),
                timestamp_writes: writes(Some(END), None),
            }));
        } else {
            let pipeline = if way == label::STREAM_COPY { &self.copy } else { &self.read };
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(if way == label::STREAM_COPY { label::STREAM_COPY } else { label::STREAM_READ }),
                timestamp_writes: writes(Some(START), Some(END)),
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(self.grid.0, self.grid.1, 1);
        }
        if let Some(q) = &self.queries {
            q.resolve(&mut encoder);
        }
        ctx.queue.submit([encoder.finish()]);
        ctx.wait()?;
        let round_trip = start.elapsed().as_secs_f64();
        let gpu = match &self.queries {
            Some(q) => q.seconds(ctx)?,
            None => None,
        };
        Ok((gpu, round_trip))
    }

    /// Whether each copying way, run once more into a cleared destination, leaves it holding the
    /// source, element for element.
    fn copied(&self, ctx: &GpuContext) -> Result<bool> {
        for way in [label::STREAM_COPY, label::BUFFER_COPY] {
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            enc.clear_buffer(&self.dst, 0, None);
            ctx.queue.submit([enc.finish()]);
            self.run(ctx, way)?;
            let dst: Vec<[u32; 4]> = read_back(ctx, &self.dst, self.bytes)?;
            if !dst.iter().enumerate().all(|(i, v)| *v == element(i as u64)) {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

impl BandwidthReport {
    /// The table `wavetrace bandwidth` prints.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut t = format!(
            "{} ({}), buffers of {}, median [min–max] of {} repetitions, GB/s (bytes read + written)\n",
            self.adapter.name,
            self.adapter.backend,
            crate::gpu::buffers::human_bytes(self.buffer_bytes),
            self.repetitions
        );
        let _ = writeln!(t, "{:<14} {:>28} {:>28}", "way", "GPU (timestamps)", "round trip");
        for w in &self.ways {
            let spread = |s: &Spread| format!("{:.1} [{:.1}–{:.1}]", s.median, s.min, s.max);
            let gpu = w.gpu_gb_per_s.as_ref().map_or("– (no timestamps)".to_string(), spread);
            let _ = writeln!(t, "{:<14} {:>28} {:>28}", w.way, gpu, spread(&w.round_trip_gb_per_s));
        }
        let _ = writeln!(t, "copy checked: {}", if self.copy_ok { "ok" } else { "WRONG" });
        t
    }
}
