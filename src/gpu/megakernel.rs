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
use super::buffers::{read_back, storage_entry, storage_zeroed, uniform_entry, Staging};
use super::context::GpuContext;
use super::dispatch_plan::{self, DispatchUniforms};
use super::gpu_render::GpuRender;
use super::instrument::SimdCounters;
use super::label;
use super::loop_limit::{check_loop_limit, paths_per_thread};
use super::memory::{MemoryCategory, MemoryLedger};
use super::scene_buffers::{decode_failures, SceneBuffers, FAILURE_BYTES};
use super::shaders::{self, Hook};
use super::stage::{Stage, Workgroups};
use super::timing::{GpuTimer, Measure, MAX_PASSES_PER_BATCH};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::{DispatchParams, FilmPixel};
use crate::numerics::Failures;
pub use crate::options::MegakernelOptions;
use crate::options::Schedule;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use std::time::Instant;

/// Persistent threads of the regenerating megakernel when `--threads` is not given, on adapters
/// other than discrete GPUs: on llvmpipe the fastest of 2^10–2^16 (`pool_memory.json`, README).
pub const DEFAULT_THREADS: u32 = 1 << 16;

/// The default on a discrete GPU. wgpu does not say how many threads an adapter holds; an H100
/// holds 132 SMs × 2048 = 270 336, so 2^16 would leave three quarters of it empty. 2^18 is 97%
/// of it, and keeps the tail where threads run out of samples short against dispatches of 2^21
/// samples. Untuned until a GPU run measures it: `experiments/baselines.json` sweeps the count.
pub const DEFAULT_THREADS_DISCRETE: u32 = 1 << 18;

/// The default persistent threads for this adapter.
pub fn default_threads(ctx: &GpuContext) -> u32 {
    if ctx.summary.device_type == format!("{:?}", wgpu::DeviceType::DiscreteGpu) {
        DEFAULT_THREADS_DISCRETE
    } else {
        DEFAULT_THREADS
    }
}

/// The persistent threads a regenerating render launches: `threads` rounded up to whole
/// workgroups, refused when zero or beyond what one dispatch can launch on `ctx`.
pub fn persistent_threads(ctx: &GpuContext, threads: Option<u32>, workgroup_size: u32) -> Result<u32> {
    let asked = threads.unwrap_or_else(|| default_threads(ctx));
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
    let opts = &opts.resolve();
    crate::options::check_megakernel(opts)?;
    ctx.check_workgroup_size(opts.workgroup_size)?;
    check_loop_limit(ctx, scene, settings)?;
    let regenerate = opts.schedule == Schedule::Regenerate;
    let threads =
        regenerate.then(|| persistent_threads(ctx, opts.threads, opts.workgroup_size)).transpose()?;
    // Where the driver caps loops: most paths a persistent thread starts per dispatch.
    let cap = regenerate
        .then(|| paths_per_thread(ctx, scene, settings).map(|p| opts.paths_per_thread.unwrap_or(p).max(1)))
        .flatten();
    let start = Instant::now();
    let mut memory = MemoryLedger::default();
    let frame = scene.frame_uniform(camera, settings);
    let scene_buffers = SceneBuffers::new(ctx, scene, &frame, settings, measure.specialize, &mut memory)?;
    let pixels = settings.width * settings.height;
    let plan = plan_dispatches(ctx, settings, opts, threads, cap);
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
    let work = regenerate.then(|| work_counters(ctx, &mut memory)).transpose()?;
    let accumulate = Accumulate::new(ctx, &samples, &film, &params, false, measure.shader_checks)?;
    let simd = instrument.then(|| SimdCounters::new(ctx, &mut memory)).transpose()?;

    let (layout, group) = trace_bindings(ctx, &samples, &params, work.as_ref());
    let mut layouts = vec![&scene_buffers.layout, &layout];
    layouts.extend(simd.as_ref().map(|s| &s.layout));
    let stage = trace_stage(ctx, opts, &measure, &scene_buffers, &layouts)?;
    let trace = Trace { stage, scene: &scene_buffers.bind_group, group: &group, simd: simd.as_ref() };

    let mut timer = GpuTimer::new(ctx, measure.timing, measure.preheat_seconds, &mut memory);
    // Checked dispatches count failures per accepted attempt (a retried one would count twice).
    let (dispatches, checked_failures) = match (threads, &work, cap) {
        (Some(threads), Some(work), Some(cap)) => {
            let mut run =
                Checked::new(ctx, &trace, &accumulate, work, &scene_buffers.failures, threads, opts);
            let n = run.render(&plan, &params, cap, &mut timer, on_progress)?;
            (n, Some(run.counted))
        }
        _ => {
            let batched = Batched { trace: &trace, accumulate: &accumulate, work: work.as_ref(), threads };
            (batched.render(ctx, &plan, &params, opts, settings, &mut timer, on_progress)?, None)
        }
    };
    memory.transient(film_bytes);
    let data: Vec<FilmPixel> = read_back(ctx, &film, film_bytes)?;
    let film = Film::from_gpu(settings.width, settings.height, settings.spp, &data);
    let failures = checked_failures.map_or_else(|| scene_buffers.read_failures(ctx), Ok)?;
    let in_flight = threads.map_or(most_samples, |t| (t as u64).min(most_samples)).max(1);
    Ok(GpuRender {
        film,
        timings: timer.into_timings(),
        // Trace and accumulate passes, none of them empty.
        dispatches,
        compute_passes: dispatches,
        empty_dispatches: Some(0),
        wall_seconds: start.elapsed().as_secs_f64(),
        simd: simd.as_ref().map(|s| s.read(ctx)).transpose()?,
        // The sample buffer (and work counters) over the paths in flight: one per sample of the
        // largest dispatch, or one per persistent thread.
        bytes_per_path: (samples.size() + work.as_ref().map_or(0, |w| w.size())).div_ceil(in_flight),
        memory: memory.summary(),
        failures,
        threads,
    })
}

/// The dispatches a render is cut into: at most `samples_per_dispatch` samples each, and for the
/// regenerating schedule no more than its persistent `threads` can take.
fn plan_dispatches(
    ctx: &GpuContext,
    settings: &RenderSettings,
    opts: &MegakernelOptions,
    threads: Option<u32>,
    cap: Option<u32>,
) -> Vec<DispatchParams> {
    let pixels = settings.width * settings.height;
    match threads {
        None => {
            let max_threads =
                ctx.summary.max_compute_workgroups_per_dimension.saturating_mul(opts.workgroup_size);
            dispatch_plan::plan(pixels, settings.spp, opts.samples_per_dispatch, max_threads)
        }
        Some(threads) => {
            // Where loops are capped, a thread starts a bounded number of paths per dispatch,
            // so a dispatch holds no more samples than its threads can take.
            let per_thread = cap.map_or(u64::MAX, u64::from);
            let budget = opts.samples_per_dispatch.min((threads as u64).saturating_mul(per_thread));
            dispatch_plan::plan(pixels, settings.spp, budget, u32::MAX)
        }
    }
}

/// Regenerating: the dispatch's next sample, the samples finished and the threads cut short
/// over the render.
fn work_counters(ctx: &GpuContext, memory: &mut MemoryLedger) -> Result<wgpu::Buffer> {
    let usage = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    Ok(memory.track(MemoryCategory::Counters, storage_zeroed(ctx, "work counters", 16, usage)?))
}

/// The trace kernel's own bindings: the samples, the dispatch's uniforms and, regenerating, the
/// work counters.
fn trace_bindings(
    ctx: &GpuContext,
    samples: &wgpu::Buffer,
    params: &DispatchUniforms,
    work: Option<&wgpu::Buffer>,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let mut entries = vec![storage_entry(0, false), uniform_entry(1, true)];
    entries.extend(work.map(|_| storage_entry(2, false)));
    let layout = ctx.bind_group_layout(label::MEGAKERNEL, &entries);
    let mut bind = vec![
        wgpu::BindGroupEntry { binding: 0, resource: samples.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 1, resource: params.binding() },
    ];
    bind.extend(work.map(|w| wgpu::BindGroupEntry { binding: 2, resource: w.as_entire_binding() }));
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label::MEGAKERNEL),
        layout: &layout,
        entries: &bind,
    });
    (layout, group)
}

/// The trace kernel of the schedule, with its hooks selected and its constants set.
fn trace_stage(
    ctx: &GpuContext,
    opts: &MegakernelOptions,
    measure: &Measure,
    scene_buffers: &SceneBuffers,
    layouts: &[&wgpu::BindGroupLayout],
) -> Result<Stage> {
    let instrumented = (Hook::Instrument, measure.instrument);
    let (pass_label, source) = match opts.schedule == Schedule::Regenerate {
        false => (label::MEGAKERNEL, shaders::MEGAKERNEL.select(&[instrumented])),
        // Samples taken per subgroup where the adapter has subgroups.
        true => (
            label::MEGAKERNEL_REGENERATE,
            shaders::MEGAKERNEL_REGENERATE
                .select(&[instrumented, (Hook::TakeSampleSubgroup, ctx.summary.subgroups)]),
        ),
    };
    let module = ctx.shader(pass_label, source, measure.shader_checks)?;
    let constants = [("WORKGROUP_SIZE", opts.workgroup_size as f64)];
    Stage::new(ctx, pass_label, &module, layouts, &scene_buffers.constants(&constants))
}

/// Words of the regenerating megakernel's `work` buffer (`shaders/megakernel_regenerate.wgsl`).
const WORK_FINISHED: usize = 1;
const WORK_CUT: usize = 2;
const WORK_PATHS_PER_THREAD: u64 = 3;

/// The trace pass and what it binds.
struct Trace<'a> {
    stage: Stage,
    scene: &'a wgpu::BindGroup,
    group: &'a wgpu::BindGroup,
    simd: Option<&'a SimdCounters>,
}

impl Trace<'_> {
    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        offset: u32,
        threads: u32,
        wg: u32,
    ) {
        let mut groups = vec![(self.scene, vec![]), (self.group, vec![offset])];
        groups.extend(self.simd.map(|s| (&s.bind_group, vec![])));
        self.stage.record(enc, timer, None, &groups, Workgroups::Direct(threads.div_ceil(wg)));
    }
}

/// Dispatches recorded in batches, the host waiting only between batches: the naive megakernel
/// (one thread per sample), and the regenerating one where the driver does not cap loops.
struct Batched<'a> {
    trace: &'a Trace<'a>,
    accumulate: &'a Accumulate,
    work: Option<&'a wgpu::Buffer>,
    threads: Option<u32>,
}

impl Batched<'_> {
    /// Records and runs the plan; returns the passes dispatched. Regenerating, the threads'
    /// paths are not capped, and every sample asked must have been taken.
    #[allow(clippy::too_many_arguments)]
    fn render(
        &self,
        ctx: &GpuContext,
        plan: &[DispatchParams],
        params: &DispatchUniforms,
        opts: &MegakernelOptions,
        settings: &RenderSettings,
        timer: &mut GpuTimer,
        on_progress: &dyn Fn(u64),
    ) -> Result<u64> {
        if let Some(work) = self.work {
            ctx.queue.write_buffer(work, 4 * WORK_PATHS_PER_THREAD, bytemuck::bytes_of(&u32::MAX));
        }
        let wg = opts.workgroup_size;
        // Two passes (trace, accumulate) per dispatch.
        let per_submit = opts.dispatches_per_submit.clamp(1, MAX_PASSES_PER_BATCH / 2) as usize;
        let mut done = 0u64;
        for (batch_index, batch) in plan.chunks(per_submit).enumerate() {
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            for (i, d) in batch.iter().enumerate() {
                let offset = params.offset(batch_index * per_submit + i);
                let samples = d.pixel_count * d.sample_count;
                let launched = match (self.threads, self.work) {
                    (Some(threads), Some(work)) => {
                        // The dispatch's next sample starts at 0 (the first word only).
                        enc.clear_buffer(work, 0, Some(4));
                        threads.min(samples.next_multiple_of(wg))
                    }
                    _ => samples,
                };
                self.trace.record(&mut enc, timer, offset, launched, wg);
                self.accumulate.record(&mut enc, timer, offset, d.pixel_count);
            }
            timer.submit_batch(ctx, enc)?;
            done += batch.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).sum::<u64>();
            on_progress(done);
        }
        if let Some(work) = self.work {
            check_finished(ctx, work, settings.sample_count())?;
        }
        Ok(2 * plan.len() as u64)
    }
}

/// The regenerating megakernel where the driver caps loops (llvmpipe): each dispatch runs on its
/// own and is checked before its samples are accumulated. A persistent thread adds up many
/// paths' loops, and the paths-per-thread estimate can fall short on a scene whose rays visit
/// many BVH nodes; a dispatch whose threads the driver cut is traced again with a quarter of
/// the paths per thread (and more launches), so the render still completes, slower.
struct Checked<'a> {
    ctx: &'a GpuContext,
    trace: &'a Trace<'a>,
    accumulate: &'a Accumulate,
    work: &'a wgpu::Buffer,
    /// The scene's failure counters, cleared before each attempt and added to `counted` after
    /// the accepted one.
    failures: &'a wgpu::Buffer,
    counted: Failures,
    threads: u32,
    wg: u32,
    /// Where each attempt's work and failure counters are copied at the end of its submission.
    work_staging: Staging,
    failures_staging: Staging,
}

impl<'a> Checked<'a> {
    fn new(
        ctx: &'a GpuContext,
        trace: &'a Trace<'a>,
        accumulate: &'a Accumulate,
        work: &'a wgpu::Buffer,
        failures: &'a wgpu::Buffer,
        threads: u32,
        opts: &MegakernelOptions,
    ) -> Self {
        Checked {
            ctx,
            trace,
            accumulate,
            work,
            failures,
            counted: Failures::default(),
            threads,
            wg: opts.workgroup_size,
            work_staging: Staging::new(ctx, "work counters read-back", 12),
            failures_staging: Staging::new(ctx, "failure counters read-back", FAILURE_BYTES),
        }
    }

    fn render(
        &mut self,
        plan: &[DispatchParams],
        params: &DispatchUniforms,
        mut per_thread: u32,
        timer: &mut GpuTimer,
        on_progress: &dyn Fn(u64),
    ) -> Result<u64> {
        let ctx = self.ctx;
        let mut dispatches = 0;
        let mut done = 0u64;
        for (i, d) in plan.iter().enumerate() {
            let offset = params.offset(i);
            let samples = d.pixel_count * d.sample_count;
            let threads = self.threads.min(samples.next_multiple_of(self.wg));
            loop {
                ctx.queue.write_buffer(self.work, 4 * WORK_PATHS_PER_THREAD, bytemuck::bytes_of(&per_thread));
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                enc.clear_buffer(self.work, 0, Some(12));
                enc.clear_buffer(self.failures, 0, None);
                // Each launch takes up to threads × per_thread samples from where the last stopped.
                let launches = (samples as u64).div_ceil(threads as u64 * per_thread as u64);
                for _ in 0..launches {
                    self.trace.record(&mut enc, timer, offset, threads, self.wg);
                }
                dispatches += launches;
                self.work_staging.copy(&mut enc, self.work, 12);
                self.failures_staging.copy(&mut enc, self.failures, FAILURE_BYTES);
                timer.submit_batch(ctx, enc)?;
                let words: Vec<u32> = self.work_staging.read(ctx, 12)?;
                if words[WORK_CUT] == 0 && words[WORK_FINISHED] == samples {
                    let words: Vec<u32> = self.failures_staging.read(ctx, FAILURE_BYTES)?;
                    self.counted.add(&decode_failures(&words));
                    break;
                }
                // Only a cut is healed by tracing again; without one, a count that differs means
                // samples were lost or taken twice, and another attempt would hide it.
                if words[WORK_CUT] == 0 {
                    bail!(
                        "the regenerating megakernel finished {} of {samples} samples in dispatch {i} \
                         with no thread cut short: samples were lost or taken twice (a bug; please \
                         report it with `wavetrace info`)",
                        words[WORK_FINISHED]
                    );
                }
                if per_thread == 1 {
                    bail!(
                        "the regenerating megakernel's threads were cut short by {}'s loop limit \
                         even at one path per thread: this scene's paths take too many loop \
                         iterations; use --schedule waves",
                        ctx.summary.name
                    );
                }
                let fewer = (per_thread / 4).max(1);
                log::warn!(
                    "{} cut {} regenerating threads short (loop limit): tracing dispatch {i} again \
                     with {fewer} paths per thread instead of {per_thread}",
                    ctx.summary.name,
                    words[WORK_CUT]
                );
                per_thread = fewer;
            }
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            self.accumulate.record(&mut enc, timer, offset, d.pixel_count);
            dispatches += 1;
            timer.submit_batch(ctx, enc)?;
            done += samples as u64;
            on_progress(done);
        }
        Ok(dispatches)
    }
}

/// Errors out unless the regenerating megakernel wrote every sample and no thread's loop was
/// cut short (checked once per render where no driver caps loops: a cut there would be a bug).
fn check_finished(ctx: &GpuContext, work: &wgpu::Buffer, asked: u64) -> Result<()> {
    let words: Vec<u32> = read_back(ctx, work, 12)?;
    // The counter is a u32 on the GPU: compare modulo 2^32.
    let (finished, cut) = (words[WORK_FINISHED], words[WORK_CUT]);
    if cut > 0 || finished != asked as u32 {
        bail!(
            "the regenerating megakernel had {cut} threads cut short and finished {finished} of \
             {asked} samples (mod 2^32) on {}; use --schedule waves",
            ctx.summary.name
        );
    }
    Ok(())
}
