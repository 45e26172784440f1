//! The megakernel method: one compute kernel traces whole paths, every bounce and material in
//! one loop. Two schedules (`--schedule`):
//!
//! - `waves` (`shaders/megakernel.wgsl`), the seeds' form: one thread per path sample, so a
//!   subgroup runs as long as its longest path and its lanes idle as paths end.
//! - `regenerate` (`shaders/megakernel_regenerate*.wgsl`): a fixed number of persistent threads
//!   (`--threads`) loop one bounce per iteration, and a lane whose path ends takes the next
//!   sample from an atomic counter (one atomic per subgroup where the adapter has subgroups):
//!   Aila & Laine (2009) and Novák et al. (2010).
//!
//! Either way the render is cut into dispatches of at most `samples_per_dispatch` samples, so no
//! dispatch runs long enough to trip a driver watchdog. Each sample's radiance lands at its index
//! in a per-dispatch buffer and the accumulate pass adds them to the film in sample order, so the
//! two schedules give the same film, and the same settings bit-identical films.

use super::accumulate::Accumulate;
use super::buffers::{read_back, storage_entry, storage_zeroed, uniform_entry};
use super::context::GpuContext;
use super::dispatch_plan::{self, DispatchUniforms};
use super::gpu_render::GpuRender;
use super::instrument::SimdCounters;
use super::loop_limit::{check_loop_limit, paths_per_thread};
use super::memory::{MemoryCategory, MemoryLedger};
use super::scene_buffers::SceneBuffers;
use super::schedule::Schedule;
use super::stage::{Stage, Workgroups};
use super::timing::{GpuTimer, Measure, MAX_PASSES_PER_BATCH};
use super::{label, shaders};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::FilmPixel;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use std::time::Instant;

/// Persistent threads of the regenerating megakernel when `--threads` is not given. wgpu does
/// not say how many threads an adapter holds; 2^16 is a fixed number near a data-centre GPU's
/// (an H100 holds 132 × 2048) that keeps the tail, where threads run out of samples, short
/// against dispatches of 2^21 samples. On llvmpipe it was the fastest of 2^10–2^16
/// (`pool_memory.json`, README).
pub const DEFAULT_THREADS: u32 = 1 << 16;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MegakernelOptions {
    /// Threads per workgroup (the seeds' block size).
    pub workgroup_size: u32,
    /// Most path samples per dispatch: bounds the time of one dispatch.
    pub samples_per_dispatch: u64,
    /// Dispatches per submission; the host waits (and updates progress) between submissions.
    pub dispatches_per_submit: u32,
    /// One thread per sample (`waves`) or persistent threads that regenerate paths.
    pub schedule: Schedule,
    /// `regenerate`: persistent threads per dispatch (None: [`DEFAULT_THREADS`]).
    pub threads: Option<u32>,
}

impl Default for MegakernelOptions {
    fn default() -> Self {
        Self {
            workgroup_size: 64,
            samples_per_dispatch: 1 << 21,
            dispatches_per_submit: 16,
            schedule: Schedule::Waves,
            threads: None,
        }
    }
}

/// The persistent threads a regenerating render launches: `threads` rounded up to whole
/// workgroups, refused when zero or beyond what one dispatch can launch on `ctx`.
pub fn persistent_threads(ctx: &GpuContext, threads: Option<u32>, workgroup_size: u32) -> Result<u32> {
    let asked = threads.unwrap_or(DEFAULT_THREADS);
    let max = ctx.summary.max_compute_workgroups_per_dimension as u64 * workgroup_size as u64;
    if asked == 0 {
        bail!("--threads must be at least 1");
    }
    if asked as u64 > max {
        bail!(
            "--threads {asked} is more than {} can launch in one dispatch ({} workgroups of {workgroup_size})",
            ctx.summary.name,
            ctx.summary.max_compute_workgroups_per_dimension
        );
    }
    Ok(asked.div_ceil(workgroup_size) * workgroup_size)
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
    let regenerate = opts.schedule == Schedule::Regenerate;
    if opts.threads.is_some() && !regenerate {
        bail!(
            "--threads sets the regenerating megakernel's persistent threads: it needs --schedule regenerate"
        );
    }
    let threads =
        regenerate.then(|| persistent_threads(ctx, opts.threads, opts.workgroup_size)).transpose()?;
    // Where the driver caps loops: most paths a persistent thread starts per dispatch.
    let cap = regenerate.then(|| paths_per_thread(ctx, scene, settings)).flatten();
    let start = Instant::now();
    let mut memory = MemoryLedger::default();
    let frame = scene.frame_uniform(camera, settings);
    let scene_buffers = SceneBuffers::new(ctx, scene, &frame, settings, &mut memory)?;
    let pixels = settings.width * settings.height;
    let plan = match threads {
        None => {
            let max_threads = limits.max_compute_workgroups_per_dimension.saturating_mul(opts.workgroup_size);
            dispatch_plan::plan(pixels, settings.spp, opts.samples_per_dispatch, max_threads)
        }
        Some(threads) => {
            // Where loops are capped, a thread starts a bounded number of paths per dispatch,
            // so a dispatch holds no more samples than its threads can take.
            let per_thread = cap.map_or(u64::MAX, u64::from);
            let budget = opts.samples_per_dispatch.min((threads as u64).saturating_mul(per_thread));
            dispatch_plan::plan(pixels, settings.spp, budget, u32::MAX)
        }
    };
    let params = DispatchUniforms::new(ctx, &plan, &mut memory);
    let film_bytes = pixels as u64 * std::mem::size_of::<FilmPixel>() as u64;
    let film = memory
        .track(MemoryCategory::Film, storage_zeroed(ctx, "film", film_bytes, wgpu::BufferUsages::COPY_SRC)?);
    let most_samples = plan.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).max().unwrap_or(1);
    let samples = memory.track(
        MemoryCategory::Samples,
        storage_zeroed(ctx, "samples", most_samples * 16, wgpu::BufferUsages::empty())?,
    );
    // Regenerating: the dispatch's next sample, the samples finished and the threads cut short
    // over the render.
    let work = regenerate
        .then(|| {
            storage_zeroed(
                ctx,
                "work counters",
                12,
                wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            )
        })
        .transpose()?
        .map(|b| memory.track(MemoryCategory::Counters, b));
    let accumulate = Accumulate::new(ctx, &samples, &film, &params)?;
    let simd = instrument.then(|| SimdCounters::new(ctx, &mut memory)).transpose()?;

    let mut entries = vec![storage_entry(0, false), uniform_entry(1, true)];
    entries.extend(work.as_ref().map(|_| storage_entry(2, false)));
    let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label::MEGAKERNEL),
        entries: &entries,
    });
    let mut bind = vec![
        wgpu::BindGroupEntry { binding: 0, resource: samples.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 1, resource: params.binding() },
    ];
    bind.extend(work.as_ref().map(|w| wgpu::BindGroupEntry { binding: 2, resource: w.as_entire_binding() }));
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label::MEGAKERNEL),
        layout: &layout,
        entries: &bind,
    });
    let mut layouts = vec![&scene_buffers.layout, &layout];
    layouts.extend(simd.as_ref().map(|s| &s.layout));
    let (pass_label, source) = match (regenerate, ctx.summary.subgroups) {
        (false, _) => (label::MEGAKERNEL, shaders::MEGAKERNEL.get(instrument)),
        (true, false) => (label::MEGAKERNEL_REGENERATE, shaders::MEGAKERNEL_REGENERATE.get(instrument)),
        (true, true) => {
            (label::MEGAKERNEL_REGENERATE, shaders::MEGAKERNEL_REGENERATE_SUBGROUP.get(instrument))
        }
    };
    let module = ctx.shader(pass_label, source)?;
    let mut constants = vec![("WORKGROUP_SIZE", opts.workgroup_size as f64)];
    if let Some(cap) = cap {
        constants.push(("PATHS_PER_THREAD", cap as f64));
    }
    let stage = Stage::new(ctx, pass_label, &module, &layouts, &scene_buffers.constants(&constants))?;

    let mut timer = GpuTimer::new(ctx, measure.timing, &mut memory);
    // Two passes (trace, accumulate) per dispatch.
    let per_submit = opts.dispatches_per_submit.clamp(1, MAX_PASSES_PER_BATCH / 2) as usize;
    let mut done = 0u64;
    for (batch_index, batch) in plan.chunks(per_submit).enumerate() {
        let mut enc =
            ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(pass_label) });
        for (i, d) in batch.iter().enumerate() {
            let offset = params.offset(batch_index * per_submit + i);
            let samples = d.pixel_count * d.sample_count;
            let launched = match threads {
                None => samples,
                Some(threads) => {
                    // The dispatch's next sample starts at 0 (the first word only).
                    enc.clear_buffer(work.as_ref().expect("regenerating"), 0, Some(4));
                    threads.min(samples.next_multiple_of(opts.workgroup_size))
                }
            };
            let mut groups = vec![(&scene_buffers.bind_group, vec![]), (&group, vec![offset])];
            groups.extend(simd.as_ref().map(|s| (&s.bind_group, vec![])));
            stage.record(
                &mut enc,
                &mut timer,
                None,
                &groups,
                Workgroups::Direct(launched.div_ceil(opts.workgroup_size)),
            );
            accumulate.record(&mut enc, &mut timer, offset, d.pixel_count);
        }
        timer.submit_batch(ctx, enc)?;
        done += batch.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).sum::<u64>();
        on_progress(done);
    }
    if let Some(work) = &work {
        check_all_finished(ctx, work, settings.sample_count())?;
    }
    memory.transient(film_bytes);
    let data: Vec<FilmPixel> = read_back(ctx, &film, film_bytes)?;
    let film = Film::from_gpu(settings.width, settings.height, settings.spp, &data);
    let in_flight = threads.map_or(most_samples, |t| (t as u64).min(most_samples)).max(1);
    Ok(GpuRender {
        film,
        timings: timer.into_timings(),
        // A trace and an accumulate pass per dispatch of the plan, none of them empty.
        dispatches: 2 * plan.len() as u64,
        empty_dispatches: Some(0),
        wall_seconds: start.elapsed().as_secs_f64(),
        simd: simd.as_ref().map(|s| s.read(ctx)).transpose()?,
        // The sample buffer (and work counters) over the paths in flight: one per sample of the
        // largest dispatch, or one per persistent thread.
        bytes_per_path: (samples.size() + work.as_ref().map_or(0, |w| w.size())).div_ceil(in_flight),
        memory: memory.summary(),
    })
}

/// Errors out unless the regenerating megakernel wrote every sample and no thread's loop was
/// cut short: a driver's loop cap ends a thread's loop mid-path, silently, and the image would
/// hold stale or truncated samples.
fn check_all_finished(ctx: &GpuContext, work: &wgpu::Buffer, asked: u64) -> Result<()> {
    let words: Vec<u32> = read_back(ctx, work, 12)?;
    // The counter is a u32 on the GPU: compare modulo 2^32.
    let (finished, cut) = (words[1], words[2]);
    if cut > 0 || finished != asked as u32 {
        bail!(
            "the regenerating megakernel had {cut} threads cut short by {}'s loop limit and \
             finished {finished} of {asked} samples (mod 2^32): this scene's paths take more loop \
             iterations than estimated; use --schedule waves",
            ctx.summary.name
        );
    }
    Ok(())
}
