//! Preheat: busy work on the GPU just before a timed frame's first submission, so the frame
//! starts with the clocks that continuous rendering holds.
//!
//! Why: the harness spends host time between frames (setup, read-back, statistics) while the GPU
//! idles, and a GPU driver lowers its clocks when the GPU is busy only part of the time. On the
//! H200 (2026-11-27, `experiments/results/nvidia-h200/megakernel_threads/`) the naive
//! megakernel's 1920x1080x16 frame took 27 ms at 1980 MHz in the first warm-up frames and 98-120
//! ms at 510-630 MHz three seconds later, each frame followed by about 0.25 s of host work. A
//! renderer that renders continuously does not pay that; without the preheat the harness charges
//! it to whichever method has the shortest frames. The preheat is not part of the frame: the
//! frame's clock starts at the first submission after it.
//!
//! Not on a software adapter (no GPU clocks; it would only cost the CPU's time).

use std::time::Instant;

use anyhow::Result;

use super::binding::storage_entry;
use super::context::GpuContext;
use super::label;

/// The busy kernel's pipeline (built once per device: the device's stage cache keeps it) and its
/// (never written) output.
struct Preheat {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
}

impl Preheat {
    fn new(ctx: &GpuContext) -> Result<Self> {
        let module = ctx.shader("preheat", super::shaders::PREHEAT, Default::default())?;
        let layout = ctx.bind_group_layout("preheat", &[storage_entry(0, false)]);
        let pipeline = ctx.stages.pipeline(label::PREHEAT, &module, &[&layout], &[], || {
            ctx.compute_pipeline(label::PREHEAT, &module, &[&layout], &[])
        })?;
        let sink = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("preheat sink"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("preheat"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: sink.as_entire_binding() }],
        });
        Ok(Self { pipeline, group })
    }

    fn submit(&self, ctx: &GpuContext, workgroups: u32) -> Result<()> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label::PREHEAT),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(workgroups, 1, 1);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }
}

/// The preheat a frame on this adapter gets when `seconds` are asked for: none on a software
/// adapter.
pub fn on(ctx: &GpuContext, seconds: f64) -> f64 {
    if ctx.summary.is_software() {
        0.0
    } else {
        seconds.max(0.0)
    }
}

/// Keeps the GPU busy for about `seconds` (host clock) and returns how long it did (0 for
/// `seconds <= 0`).
pub fn run(ctx: &GpuContext, seconds: f64) -> Result<f64> {
    if seconds <= 0.0 {
        return Ok(0.0);
    }
    let preheat = Preheat::new(ctx)?;
    let start = Instant::now();
    // Submissions of a few milliseconds each: the host's wait between them is microseconds,
    // and the last one ends close to the asked length.
    let max = ctx.summary.max_compute_workgroups_per_dimension.min(65_535);
    let mut workgroups = 256u32.min(max);
    while start.elapsed().as_secs_f64() < seconds {
        let t = Instant::now();
        preheat.submit(ctx, workgroups)?;
        if t.elapsed().as_secs_f64() < 0.002 && workgroups < max {
            workgroups = workgroups.saturating_mul(2).min(max);
        }
    }
    Ok(start.elapsed().as_secs_f64())
}
