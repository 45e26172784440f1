//! The megakernel method: one compute kernel (`shaders/megakernel.wgsl`) traces whole paths, one
//! path per thread.
//!
//! The render is cut into dispatches of at most `samples_per_dispatch` paths, so no dispatch runs
//! long enough to trip a driver watchdog. After each, the accumulate pass adds its samples to the
//! film in sample order, so the same settings give bit-identical films.

use super::accumulate::Accumulate;
use super::buffers::{storage_entry, storage_zeroed, uniform_entry};
use super::context::GpuContext;
use super::dispatch_plan::{self, DispatchUniforms};
use super::gpu_render::GpuRender;
use super::instrument::SimdCounters;
use super::loop_limit::check_loop_limit;
use super::scene_buffers::SceneBuffers;
use super::stage::{Stage, Workgroups};
use super::timing::{GpuTimer, Measure, MAX_PASSES_PER_BATCH};
use super::{label, shaders};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::FilmPixel;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::Result;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MegakernelOptions {
    /// Threads per workgroup (the seeds' block size).
    pub workgroup_size: u32,
    /// Most path samples per dispatch: bounds the time of one dispatch.
    pub samples_per_dispatch: u64,
    /// Dispatches per submission; the host waits (and updates progress) between submissions.
    pub dispatches_per_submit: u32,
}

impl Default for MegakernelOptions {
    fn default() -> Self {
        Self { workgroup_size: 64, samples_per_dispatch: 1 << 21, dispatches_per_submit: 16 }
    }
}

pub fn render(
    ctx: &GpuContext,
    scene: &PackedScene,
    camera: &CameraFrame,
    settings: &RenderSettings,
    opts: &MegakernelOptions,
    measure: Measure,
    on_progress: &dyn Fn(u64),
) -> Result<GpuRender> {
    let instrument = measure.instrument;
    settings.validate().map_err(anyhow::Error::msg)?;
    let limits = &ctx.summary;
    ctx.check_workgroup_size(opts.workgroup_size)?;
    check_loop_limit(ctx, scene, settings)?;
    let start = Instant::now();
    let frame = scene.frame_uniform(camera, settings);
    let scene_buffers = SceneBuffers::new(ctx, scene, &frame, settings)?;
    let pixels = settings.width * settings.height;
    let max_threads = limits.max_compute_workgroups_per_dimension.saturating_mul(opts.workgroup_size);
    let plan = dispatch_plan::plan(pixels, settings.spp, opts.samples_per_dispatch, max_threads);
    let params = DispatchUniforms::new(ctx, &plan);
    let film_bytes = pixels as u64 * std::mem::size_of::<FilmPixel>() as u64;
    let film = storage_zeroed(ctx, "film", film_bytes, wgpu::BufferUsages::COPY_SRC)?;
    let most_threads = plan.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).max().unwrap_or(1);
    let samples = storage_zeroed(ctx, "samples", most_threads * 16, wgpu::BufferUsages::empty())?;
    let accumulate = Accumulate::new(ctx, &samples, &film, &params)?;
    let simd = instrument.then(|| SimdCounters::new(ctx)).transpose()?;

    let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label::MEGAKERNEL),
        entries: &[storage_entry(0, false), uniform_entry(1, true)],
    });
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label::MEGAKERNEL),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: samples.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: params.binding() },
        ],
    });
    let mut layouts = vec![&scene_buffers.layout, &layout];
    layouts.extend(simd.as_ref().map(|s| &s.layout));
    let module = ctx.shader(label::MEGAKERNEL, shaders::MEGAKERNEL.get(instrument))?;
    let stage = Stage::new(
        ctx,
        label::MEGAKERNEL,
        &module,
        &layouts,
        &scene_buffers.constants(&[("WORKGROUP_SIZE", opts.workgroup_size as f64)]),
    )?;

    let mut timer = GpuTimer::new(ctx, measure.timing);
    // Two passes (trace, accumulate) per dispatch.
    let per_submit = opts.dispatches_per_submit.clamp(1, MAX_PASSES_PER_BATCH / 2) as usize;
    let mut done = 0u64;
    for (batch_index, batch) in plan.chunks(per_submit).enumerate() {
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label::MEGAKERNEL) });
        for (i, d) in batch.iter().enumerate() {
            let offset = params.offset(batch_index * per_submit + i);
            let threads = d.pixel_count * d.sample_count;
            let mut groups = vec![(&scene_buffers.bind_group, vec![]), (&group, vec![offset])];
            groups.extend(simd.as_ref().map(|s| (&s.bind_group, vec![])));
            stage.record(
                &mut enc,
                &mut timer,
                None,
                &groups,
                Workgroups::Direct(threads.div_ceil(opts.workgroup_size)),
            );
            accumulate.record(&mut enc, &mut timer, offset, d.pixel_count);
        }
        timer.submit_batch(ctx, enc)?;
        done += batch.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).sum::<u64>();
        on_progress(done);
    }
    let data: Vec<FilmPixel> = super::buffers::read_back(ctx, &film, film_bytes)?;
    let film = Film::from_gpu(settings.width, settings.height, settings.spp, &data);
    Ok(GpuRender {
        film,
        timings: timer.into_timings(),
        // A trace and an accumulate pass per dispatch of the plan, none of them empty.
        dispatches: 2 * plan.len() as u64,
        empty_dispatches: Some(0),
        wall_seconds: start.elapsed().as_secs_f64(),
        simd: simd.as_ref().map(|s| s.read(ctx)).transpose()?,
        // The sample buffer: one radiance value per path of the largest dispatch.
        bytes_per_path: 16,
    })
}
