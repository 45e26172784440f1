//! The wavefront method (Laine, Karras & Aila, HPG 2013): each bounce is split into small passes
//! over queues of paths held in GPU memory, so that each pass runs converged.
//!
//! The image's samples are cut into shares: with `--schedule waves`, waves of at most `pool`
//! paths that all start together and run `max_depth` bounces; with `--schedule regenerate`,
//! shares as large as a dispatch's parameters allow (usually the whole image), whose slots are
//! refilled as paths end (Laine et al.'s "new path" stage), so intersect and shade see a full
//! pool until the image's last samples. Finished samples wait in a ring of one-pool chunks
//! until the GPU's decision pass adds the oldest complete ones to the film. Per share:
//!
//! ```text
//! generate | regenerate_init                camera rays (waves) | every slot free (regenerate)
//! for each iteration (waves: max_depth; regenerate: until a read-back says the share is done):
//!     [queue_setup_regenerate,              (regenerate, once at most --refill-below × pool are
//!      [compact_states_find,                 live) next samples into the free slots (slot order:
//!       queue_setup_compact_states,          the lowest, in ascending order; --compact-states on:
//!       compact_states_move]                 first move the live paths below the live count, so
//!      regenerate]                           the samples take the slots from there on)
//!     queue_setup_intersect                 ray queue count → intersect's indirect args
//!     [ray_sort_count, _scan, _scatter]     (--ray-sort) order the ray queue by direction
//!                                           octant (and origin cell)
//!     intersect                             closest hits; escaped rays add the background
//!     [compact_scan, _blocks, _scatter]     (scan method) build the material queues
//!     queue_setup_shade                     material queue counts → shade passes' args
//!     shade_<kind> for each kind used       scatter; survivors → next ray queue;
//!       | shade | shade_sorted              (--nee on) diffuse hits → shadow queue (--shade
//!                                           single: one pass, a material switch; sorted: one
//!                                           pass over the material queues end to end)
//!     [compact_scan, _blocks, _scatter]     (scan method, or slot-depth order) build the next ray
//!                                           queue (slot order: over every slot, with the free
//!                                           list and the shadow queue)
//!     [slot_sweep]                          (slot order, atomic method) the same lists, by
//!                                           appends over every slot
//!     [queue_setup_shadow, shadow]          (--nee on, scene has lights) shadow rays (with the
//!                                           decision pass below folded into the setup:
//!                                           queue_setup_shadow_decide)
//!     [schedule_decide,                     (regenerate: after every iteration with the tail,
//!      [tail]                                else every --sync-every) the host's old check on
//!      accumulate_range]                     the GPU: at a check (every --sync-every; with the
//!                                           tail every iteration once every sample started)
//!                                           size the tail over the oldest chunks' last paths if
//!                                           the ring needs them back, or the share's last ones;
//!                                           complete chunks → film, in sample order; move the
//!                                           refill limit to the ring's new end; DONE once every
//!                                           chunk is in; elsewhere both passes are empty
//!     (regenerate, every --sync-every iterations: submit without waiting, the counters copied
//!      into the next staging buffer of a ring of --batches-in-flight, whose mapping is polled;
//!      at that many batches in flight, wait for the oldest's read-back; stop recording once
//!      one says DONE: the iterations recorded after are speculative, zero workgroups)
//! accumulate                                (waves) the wave's radiance → film, in sample order
//! ```
//!
//! The host never reads a counter to go on: passes whose queues are empty dispatch zero
//! workgroups (and are counted as empty), and the regenerating schedule's decisions are the GPU's.
//! It waits once per share, at its end (and with per-pass timestamps after every batch). Each
//! sample keeps its counter-based random numbers and the film adds each pixel's samples in
//! sample order under both schedules, so they give bit-identical films. (`--launch pool`: the
//! consumers are launched at the pool's size instead, their threads past the queue returning.)
//!
//! Where it lives: [`render`] below reads as plan → bindings → stages → a driver per share;
//! `plan.rs` decides what runs, `stages.rs` records one iteration as drawn above, `drive.rs`
//! drives a share per schedule, `recorder.rs` is what every pass records into.

pub mod append;
pub mod compact;
pub mod compact_states;
mod drive;
pub mod generate;
pub mod graph;
pub mod intersect;
pub mod intersect_registers;
pub mod pass;
pub mod path_state;
pub mod plan;
pub mod pool;
pub mod queue_order;
pub mod queue_setup;
pub mod ray_sort;
mod recorder;
pub mod refill;
pub mod schedule;
pub mod shade;
pub mod shadow;
pub mod share_ledger;
pub mod slot_sweep;
mod stages;
pub mod tail;
pub mod traffic;

use super::accumulate::Accumulate;
use super::buffers::{read_back, storage_zeroed, Staging};
use super::context::GpuContext;
use super::dispatch_plan::DispatchUniforms;
use super::gpu_render::GpuRender;
use super::instrument::Coherence;
use super::loop_limit::check_loop_limit;
use super::memory::{MemoryCategory, MemoryLedger};
use super::timing::{GpuTimer, Measure, Timings};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::FilmPixel;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::Result;
// The options live in `crate::options`; the wavefront's are re-exported where it is built.
use crate::layout::material_kind;
pub use crate::options::{
    Append, CompactStates, Compaction, ComputePasses, Launch, QueueOrder, RaySort, Refill, ResolvedWavefront,
    RunSchedule, Scan, Schedule, ShadePasses, ShadowRays, Tail, WavefrontOptions, BATCHES_IN_FLIGHT,
    MAX_BATCHES_IN_FLIGHT,
};
use drive::Drive;
use path_state::{QUEUE_COUNT, QUEUE_MATERIAL_0, QUEUE_SHADOW};
use plan::Plan;
pub use plan::STATS_BOUNCES;
pub use pool::{max_pool, DEFAULT_POOL};
pub use recorder::{Bindings, WaveRecorder};
pub use schedule::ScheduleStats;
use share_ledger::ShareLedger;
use stages::Stages;
use std::time::Instant;

/// Per-bounce queue sizes summed over waves: `rays[b]` paths were intersected at bounce b,
/// `materials[k][b]` shaded with material kind k (all in `materials[0]` with one shade pass) and
/// `shadow[b]` shadow rays traced (empty without `--nee on`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct QueueHistogram {
    pub rays: Vec<u64>,
    pub materials: [Vec<u64>; material_kind::COUNT],
    #[serde(default)]
    pub shadow: Vec<u64>,
}

/// What the wavefront measured besides the film.
#[derive(Clone, Debug)]
pub struct WavefrontRender {
    pub render: GpuRender,
    pub pool: u32,
    /// Per-bounce queue sizes (waves with compaction; regenerating mixes bounces in a queue).
    pub histogram: Option<QueueHistogram>,
    pub schedule: ScheduleStats,
    /// The intersect pass's coherence per iteration bucket (`--instrument`).
    pub coherence: Option<Vec<Coherence>>,
    /// The options as they ran: every `auto` and default that resolves at run time (schedule
    /// and tail, pool size, queue order, scan, append, compute passes) made concrete.
    pub resolved: WavefrontOptions,
}

/// What a render would record, without rendering (`wavetrace plan`): the options as they would
/// run, the pool and its shares, and the pass graph.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Explained {
    pub options: WavefrontOptions,
    /// The schedule that runs (`auto` resolved).
    pub schedule: Schedule,
    pub pool: u32,
    pub bytes_per_path: u64,
    pub shares: usize,
    pub graph: graph::Graph,
}

/// The plan and graph of a render of `scene` with `opts`, timed per pass or not (`timing`).
pub fn explain(
    ctx: &GpuContext,
    scene: &PackedScene,
    settings: &RenderSettings,
    opts: &WavefrontOptions,
    timing: crate::gpu::timing::Timing,
) -> Result<Explained> {
    let ResolvedWavefront { options: ref opts, schedule } = opts.resolve(ctx.summary.is_software());
    crate::options::check_wavefront(opts)?;
    let plan = Plan::new(ctx, scene, settings, opts, schedule)?;
    let times_passes = ctx.summary.timestamps && timing == crate::gpu::timing::Timing::Passes;
    let shared = opts.compute_passes == ComputePasses::Shared && !times_passes;
    let graph = graph::Graph::new(&plan, opts, ctx.device.limits().max_compute_workgroups_per_dimension);
    Ok(Explained {
        options: plan.resolved(opts, shared),
        schedule: schedule.into(),
        pool: plan.pool,
        bytes_per_path: plan.layout.bytes_per_path(),
        shares: plan.shares.len(),
        graph,
    })
}

pub fn render(
    ctx: &GpuContext,
    scene: &PackedScene,
    camera: &CameraFrame,
    settings: &RenderSettings,
    opts: &WavefrontOptions,
    measure: Measure,
    on_progress: &dyn Fn(u64),
) -> Result<WavefrontRender> {
    let ResolvedWavefront { options: ref opts, schedule } = opts.resolve(ctx.summary.is_software());
    crate::options::check_wavefront(opts)?;
    check_loop_limit(ctx, scene, settings)?;
    let plan = Plan::new(ctx, scene, settings, opts, schedule)?;
    let (pool, regenerate, ring, wg) = (plan.pool, plan.regenerate, plan.ring, opts.workgroup_size);
    let start = Instant::now();

    let mut memory = MemoryLedger::default();
    let params = DispatchUniforms::new(ctx, &plan.shares, &mut memory);
    let frame = scene.frame_uniform(camera, settings);
    let b = Bindings::new(ctx, scene, &frame, settings, &plan, measure, &params, &mut memory)?;
    let film_bytes = (settings.width * settings.height) as u64 * std::mem::size_of::<FilmPixel>() as u64;
    let film = storage_zeroed(ctx, "film", film_bytes, wgpu::BufferUsages::COPY_SRC)?;
    let film = memory.track(MemoryCategory::Film, film);
    let samples = if regenerate { &b.state.samples } else { &b.state.radiance };
    let accumulate = Accumulate::new(ctx, samples, &film, &params, regenerate, measure.shader_checks)?;
    let stages = Stages::new(ctx, &plan, &b, &accumulate, opts, measure.instrument, &mut memory)?;
    let staging = staging_ring(ctx, &plan, opts, &mut memory);
    let mut timer = GpuTimer::new(ctx, measure.timing, measure.preheat_seconds, &mut memory);
    // Per-pass timestamps need a pass per dispatch.
    let shared_passes = opts.compute_passes == ComputePasses::Shared && !timer.times_passes();
    let mut histogram = (opts.compaction != Compaction::Off && !regenerate).then(QueueHistogram::default);
    let mut stats = plan.schedule_stats(opts);
    // Path samples the GPU has finished (waves are submitted without waiting for them).
    let finished = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let mut ledger = (!regenerate).then(|| ShareLedger::new(ctx, &b.state, &mut memory));
    let mut compute_passes = 0u64;
    let drive = Drive { ctx, stages: &stages, b: &b, opts, max_depth: settings.max_depth, pool };
    for (w, d) in plan.shares.iter().enumerate() {
        let paths = d.pixel_count * d.sample_count;
        // Regenerating: this share's sample ring (the render's chunk and ring sizes).
        let r = schedule::Ring { paths, ..ring };
        let launch =
            (opts.launch == Launch::Pool).then(|| (if regenerate { pool } else { paths }).div_ceil(wg));
        let mut wave = WaveRecorder::new(ctx, shared_passes, &mut timer, &b, params.offset(w), d, launch);
        stages.record(&mut wave, graph::Phase::Start, 0, false, false);
        let iterations = match schedule {
            RunSchedule::Waves => drive.waves(&mut wave)?,
            RunSchedule::Regenerate => {
                let done = finished.load(std::sync::atomic::Ordering::Relaxed);
                drive.regenerate(&mut wave, &r, &staging, &mut stats, &|f| on_progress(done + f))?
            }
        };
        if regenerate {
            // (Drive::regenerate waited for the share's last batch.)
            stats.add_share(ctx, &b.state, r.chunks(), iterations, wave.dispatches)?;
        } else {
            let ledger = ledger.as_mut().expect("waves keep a share ledger");
            let last = w + 1 == plan.shares.len();
            drive.end_wave(&mut wave, iterations, ledger, last, &mut stats, histogram.as_mut())?;
        }
        compute_passes += wave.compute_passes;
        count_when_done(ctx, &finished, paths as u64, on_progress)?;
    }

    let timings = close_counts(&plan, opts, settings, &mut stats, histogram.as_mut(), timer);
    memory.transient(film_bytes);
    let film =
        Film::from_gpu(settings.width, settings.height, settings.spp, &read_back(ctx, &film, film_bytes)?);
    let coherence = b.simd.as_ref().map(|s| s.read_coherence(ctx)).transpose()?;
    Ok(WavefrontRender {
        render: GpuRender {
            film,
            timings,
            dispatches: stats.dispatches,
            compute_passes,
            empty_dispatches: Some(stats.empty_dispatches),
            wall_seconds: start.elapsed().as_secs_f64(),
            simd: b.simd.as_ref().map(|s| s.read(ctx)).transpose()?,
            bytes_per_path: plan.layout.bytes_per_path(),
            memory: memory.summary(),
            failures: b.scene.read_failures(ctx)?,
            threads: None,
        },
        pool,
        histogram,
        schedule: stats,
        coherence,
        resolved: plan.resolved(opts, shared_passes),
    })
}

/// The render's timings, once its counts are closed: the histogram trimmed, and the state
/// traffic modelled from the counts (with queues) and given the passes' times.
fn close_counts(
    plan: &Plan,
    opts: &WavefrontOptions,
    settings: &RenderSettings,
    stats: &mut ScheduleStats,
    histogram: Option<&mut QueueHistogram>,
    timer: GpuTimer,
) -> Timings {
    let histogram = histogram.map(|h| {
        h.trim();
        &*h
    });
    if opts.compaction != Compaction::Off {
        stats.state_traffic = Some(model_traffic(plan, opts, settings, stats, histogram));
    }
    let timings = timer.into_timings();
    if let Some(t) = &mut stats.state_traffic {
        t.add_times(&timings);
    }
    timings
}

/// Adds `paths` to `finished` once the GPU has done what is submitted, and reports what has
/// finished so far (without waiting: waves are submitted ahead).
fn count_when_done(
    ctx: &GpuContext,
    finished: &std::sync::Arc<std::sync::atomic::AtomicU64>,
    paths: u64,
    on_progress: &dyn Fn(u64),
) -> Result<()> {
    let count = finished.clone();
    ctx.queue.on_submitted_work_done(move || {
        count.fetch_add(paths, std::sync::atomic::Ordering::Relaxed);
    });
    // Runs the callbacks of whatever has finished, without waiting.
    ctx.device.poll(wgpu::PollType::Poll).map_err(|e| anyhow::anyhow!("polling the GPU failed: {e}"))?;
    on_progress(finished.load(std::sync::atomic::Ordering::Relaxed));
    Ok(())
}

/// Regenerating: the ring of staging buffers the batches in flight read the schedule's counters
/// back through (none in waves).
fn staging_ring(
    ctx: &GpuContext,
    plan: &Plan,
    opts: &WavefrontOptions,
    memory: &mut MemoryLedger,
) -> Vec<Staging> {
    let batches = if plan.regenerate { opts.batches_in_flight } else { 0 };
    (0..batches)
        .map(|_| {
            let bytes = schedule::ChunkCounters::bytes(&plan.ring);
            memory.add(MemoryCategory::Counters, bytes);
            Staging::new(ctx, "schedule counters read-back", bytes)
        })
        .collect()
}

/// The render's modelled path-state traffic from its counters: the camera rays' bounce apart
/// in waves' queue histogram; regenerating, counted where camera rays are made in place (their
/// marks tell them apart).
fn model_traffic(
    plan: &Plan,
    opts: &WavefrontOptions,
    settings: &RenderSettings,
    stats: &ScheduleStats,
    histogram: Option<&QueueHistogram>,
) -> traffic::StateTraffic {
    let mut items = traffic_items(stats, settings, plan.pool, plan.shares.len());
    items.first_bounce = match histogram {
        Some(h) => {
            let camera_hits = h.materials.iter().map(|m| m.first().copied().unwrap_or(0)).sum();
            Some((camera_hits, h.rays.get(1).copied().unwrap_or(0)))
        }
        None => (plan.regenerate && plan.camera_in_place).then_some(stats.first_bounce),
    };
    traffic::StateTraffic::model(&plan.traffic_shape(opts), &items)
}

/// The item counts of [`traffic::StateTraffic::model`] from a render's counters.
fn traffic_items(
    stats: &ScheduleStats,
    settings: &RenderSettings,
    pool: u32,
    shares: usize,
) -> traffic::Items {
    let q = &stats.queued;
    let samples = settings.sample_count();
    let regenerate = stats.schedule == Schedule::Regenerate;
    traffic::Items {
        samples,
        rays: q[0] + q[1], // the two ray queues
        hits: std::array::from_fn(|k| q[QUEUE_MATERIAL_0 as usize + k]),
        shadow: q[QUEUE_SHADOW as usize],
        tail_paths: stats.tail_paths,
        // Passes over every slot: the pool per iteration, or each wave's paths per bounce.
        slot_visits: if regenerate {
            stats.iterations * pool as u64
        } else {
            settings.max_depth as u64 * samples
        },
        init_slots: if regenerate { shares as u64 * pool as u64 } else { 0 },
        first_bounce: None,
        refilled: stats.refilled_in_place.map_or((0, 0), |r| (r.intersect, r.shade)),
    }
}

/// Adds a wave's queue sizes per bounce (`rows`: `bounces` rows of `QUEUE_COUNT` words from
/// `COUNTER_STATS`, as the share left them) to the histogram.
fn add_histogram_rows(h: &mut QueueHistogram, rows: &[u32], bounces: usize) {
    let row = |b: usize, q: usize| rows[b * QUEUE_COUNT as usize + q] as u64;
    h.rays.resize(bounces, 0);
    for b in 0..bounces {
        h.rays[b] += row(b, 0);
    }
    for (k, m) in h.materials.iter_mut().enumerate() {
        m.resize(bounces, 0);
        for (b, v) in m.iter_mut().enumerate() {
            *v += row(b, QUEUE_MATERIAL_0 as usize + k);
        }
    }
    h.shadow.resize(bounces, 0);
    for b in 0..bounces {
        h.shadow[b] += row(b, QUEUE_SHADOW as usize);
    }
}

impl QueueHistogram {
    /// Drops the bounces no path reached.
    fn trim(&mut self) {
        let used = self.rays.iter().rposition(|&n| n > 0).map_or(0, |i| i + 1);
        self.rays.truncate(used);
        for m in &mut self.materials {
            m.truncate(used);
        }
        self.shadow.truncate(used);
        if self.shadow.iter().all(|&n| n == 0) {
            self.shadow.clear();
        }
    }
}
