//! The megakernel method: one compute kernel (`shaders/megakernel.wgsl`) traces whole paths.
//!
//! The render is cut into dispatches of at most `samples_per_dispatch` path samples, so no
//! single dispatch runs long enough to trip a driver watchdog. Within a dispatch each pixel has
//! one thread; a pixel's dispatches run in sample order, so accumulation is deterministic.

use super::buffers::{storage_entry, storage_zeroed, uniform_entry};
use super::context::GpuContext;
use super::scene_buffers::SceneBuffers;
use super::timing::{GpuTimer, Timings, MAX_PASSES_PER_BATCH};
use super::{label, shaders};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::{DispatchParams, FilmPixel};
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MegakernelOptions {
    /// Threads per workgroup (the seeds' block size).
    pub workgroup_size: u32,
    /// Upper bound on path samples per dispatch: bounds the time of one dispatch.
    pub samples_per_dispatch: u64,
    /// Dispatches per submission; the host waits (and updates progress) between submissions.
    pub dispatches_per_submit: u32,
}

impl Default for MegakernelOptions {
    fn default() -> Self {
        Self { workgroup_size: 64, samples_per_dispatch: 1 << 21, dispatches_per_submit: 16 }
    }
}

/// A GPU render's film and how it went.
#[derive(Clone, Debug)]
pub struct GpuRender {
    pub film: Film,
    pub timings: Timings,
    pub dispatches: u64,
    pub wall_seconds: f64,
}

/// Splits the render into dispatches: sample chunks outermost, so every pixel sees its samples
/// in increasing order; pixel chunks within, each at most `max_threads` pixels.
pub fn plan_dispatches(pixels: u32, spp: u32, samples_per_dispatch: u64, max_threads: u32) -> Vec<DispatchParams> {
    let pixels_per = (pixels as u64).min(max_threads as u64).min(samples_per_dispatch.max(1)).max(1) as u32;
    let samples_per = (samples_per_dispatch / pixels_per as u64).clamp(1, spp as u64) as u32;
    let mut plan = Vec::new();
    let mut s = 0;
    while s < spp {
        let sample_count = samples_per.min(spp - s);
        let mut p = 0;
        while p < pixels {
            let pixel_count = pixels_per.min(pixels - p);
            plan.push(DispatchParams { pixel_offset: p, pixel_count, sample_start: s, sample_count });
            p += pixel_count;
        }
        s += sample_count;
    }
    plan
}

pub fn render(
    ctx: &GpuContext,
    scene: &PackedScene,
    camera: &CameraFrame,
    settings: &RenderSettings,
    opts: &MegakernelOptions,
    on_progress: &dyn Fn(u64),
) -> Result<GpuRender> {
    settings.validate().map_err(anyhow::Error::msg)?;
    let limits = &ctx.summary;
    if opts.workgroup_size == 0 || opts.workgroup_size > limits.max_compute_invocations_per_workgroup {
        bail!(
            "workgroup size {} is outside 1..={} on {}",
            opts.workgroup_size,
            limits.max_compute_invocations_per_workgroup,
            limits.name
        );
    }
    let start = Instant::now();
    let frame = scene.frame_uniform(camera, settings);
    let scene_buffers = SceneBuffers::new(ctx, scene, &frame)?;
    let pixels = settings.width * settings.height;
    let film_bytes = pixels as u64 * std::mem::size_of::<FilmPixel>() as u64;
    let film = storage_zeroed(ctx, "film", film_bytes, wgpu::BufferUsages::COPY_SRC)?;

    let max_threads = limits.max_compute_workgroups_per_dimension.saturating_mul(opts.workgroup_size);
    let plan = plan_dispatches(pixels, settings.spp, opts.samples_per_dispatch, max_threads);
    let stride = ctx.device.limits().min_uniform_buffer_offset_alignment.max(16) as usize;
    let mut params = vec![0u8; plan.len() * stride];
    for (i, d) in plan.iter().enumerate() {
        params[i * stride..i * stride + 16].copy_from_slice(bytemuck::bytes_of(d));
    }
    let params_buf = wgpu::util::DeviceExt::create_buffer_init(
        &ctx.device,
        &wgpu::util::BufferInitDescriptor { label: Some("dispatch params"), contents: &params, usage: wgpu::BufferUsages::UNIFORM },
    );

    let film_layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("megakernel film"),
        entries: &[storage_entry(0, false), uniform_entry(1, true)],
    });
    let film_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("megakernel film"),
        layout: &film_layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: film.as_entire_binding() },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &params_buf,
                    offset: 0,
                    size: wgpu::BufferSize::new(16),
                }),
            },
        ],
    });
    let layout = ctx.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label::MEGAKERNEL),
        bind_group_layouts: &[Some(&scene_buffers.layout), Some(&film_layout)],
        immediate_size: 0,
    });
    let module = ctx.shader(label::MEGAKERNEL, shaders::MEGAKERNEL)?;
    let pipeline = ctx.compute_pipeline(
        label::MEGAKERNEL,
        &module,
        &layout,
        &[("WORKGROUP_SIZE", opts.workgroup_size as f64)],
    )?;

    let mut timer = GpuTimer::new(ctx);
    let per_submit = opts.dispatches_per_submit.clamp(1, MAX_PASSES_PER_BATCH) as usize;
    let mut done = 0u64;
    for (batch_index, batch) in plan.chunks(per_submit).enumerate() {
        let mut enc = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label::MEGAKERNEL) });
        for (i, d) in batch.iter().enumerate() {
            let offset = ((batch_index * per_submit + i) * stride) as u32;
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label::MEGAKERNEL),
                timestamp_writes: timer.pass(label::MEGAKERNEL),
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &scene_buffers.bind_group, &[]);
            pass.set_bind_group(1, &film_group, &[offset]);
            pass.dispatch_workgroups(d.pixel_count.div_ceil(opts.workgroup_size), 1, 1);
        }
        timer.resolve(&mut enc);
        ctx.queue.submit([enc.finish()]);
        timer.submitted();
        timer.finish_batch(ctx)?;
        done += batch.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).sum::<u64>();
        on_progress(done);
    }
    let data: Vec<FilmPixel> = super::buffers::read_back(ctx, &film, film_bytes)?;
    let film = Film::from_gpu(settings.width, settings.height, settings.spp, &data);
    Ok(GpuRender { film, timings: timer.into_timings(), dispatches: plan.len() as u64, wall_seconds: start.elapsed().as_secs_f64() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_covers_every_pixel_sample_once_in_sample_order() {
        for (pixels, spp, budget, max_threads) in [(100, 7, 64, 1000), (10, 100, 1 << 20, 1000), (5000, 3, 1 << 20, 1024)] {
            let plan = plan_dispatches(pixels, spp, budget, max_threads);
            let mut next = vec![0u32; pixels as usize];
            for d in &plan {
                assert!(d.pixel_count <= max_threads);
                assert!(d.pixel_count as u64 * d.sample_count as u64 <= budget.max(spp as u64 * 0 + d.pixel_count as u64));
                for p in d.pixel_offset..d.pixel_offset + d.pixel_count {
                    assert_eq!(next[p as usize], d.sample_start, "pixel {p} sees samples in order");
                    next[p as usize] += d.sample_count;
                }
            }
            assert!(next.iter().all(|&n| n == spp));
        }
    }
}
