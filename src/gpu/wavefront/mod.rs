//! The wavefront method (Laine, Karras & Aila, HPG 2013): each bounce is split into small passes
//! over queues of paths held in GPU memory, so that each pass runs converged.
//!
//! The image's samples are cut into shares: with `--schedule waves`, waves of at most `pool`
//! paths that all start together and run `max_depth` bounces; with `--schedule regenerate`,
//! shares as large as a dispatch's parameters allow (usually the whole image), whose slots are
//! refilled as paths end (Laine et al.'s "new path" stage), so intersect and shade see a full
//! pool until the image's last samples. Finished samples wait in a ring of one-pool chunks
//! until the host adds the oldest complete ones to the film. Per share:
//!
//! ```text
//! generate | regenerate_init                camera rays (waves) | every slot free (regenerate)
//! for each iteration (waves: max_depth; regenerate: until the share's samples are done):
//!     (regenerate, every --sync-every iterations, and with the tail every iteration once
//!      every sample has started: read the counters back, then
//!      [queue_setup_tail, tail]             finish the oldest chunks' last paths if the ring
//!                                           needs them back, or the share's last paths
//!      accumulate_range                     complete chunks → film, in sample order
//!      and move the refill limit to the ring's new end)
//!     [queue_setup_regenerate,              (regenerate, once at most --refill-below × pool are
//!      [compact_states_find,                 live) next samples into the free slots (slot order:
//!       queue_setup_compact_states,          the lowest, in ascending order; --compact-states on:
//!       compact_states_move]                 first move the live paths below the live count, so
//!      regenerate]                           the samples take the slots from there on)
//!     queue_setup_intersect                 ray queue count → intersect's indirect args
//!     [sort_rays_count, _scan, _scatter]    (--ray-sort) order the ray queue by direction
//!                                           octant (and origin cell)
//!     intersect                             closest hits; escaped rays add the background
//!     [compact_scan, _blocks, _scatter]     (scan method) build the material queues
//!     queue_setup_shade                     material queue counts → shade passes' args
//!     shade_<kind> for each kind used       scatter; survivors → next ray queue;
//!                                           (--nee on) diffuse hits → shadow queue
//!     [compact_scan, _blocks, _scatter]     (scan method, or slot-depth order) build the next ray
//!                                           queue (slot order: over every slot, with the free
//!                                           list and the shadow queue)
//!     [slot_sweep]                          (slot order, atomic method) the same lists, by
//!                                           appends over every slot
//!     [queue_setup_shadow, shadow]          (--nee on, scene has lights) shadow rays
//! accumulate                                (waves) the wave's radiance → film, in sample order
//! ```
//!
//! The host never reads a counter inside a batch of iterations: passes whose queues are empty
//! dispatch zero workgroups (and are counted as empty). Each sample keeps its counter-based
//! random numbers and the film adds each pixel's samples in sample order under both schedules,
//! so they give bit-identical films.

pub mod append;
pub mod compact;
pub mod compact_states;
pub mod compute_passes;
pub mod generate;
pub mod intersect;
pub mod intersect_registers;
pub mod path_state;
pub mod queue_order;
pub mod queue_setup;
pub mod ray_sort;
pub mod refill;
pub mod schedule;
pub mod shade;
pub mod shadow;
pub mod share_ledger;
pub mod slot_sweep;
pub mod tail;

use super::accumulate::Accumulate;
use super::buffers::{read_back, storage_zeroed, Staging};
use super::context::GpuContext;
use super::dispatch_plan::DispatchUniforms;
use super::gpu_render::GpuRender;
use super::instrument::{Coherence, SimdCounters};
use super::loop_limit::check_loop_limit;
use super::memory::{MemoryCategory, MemoryLedger};
use super::scene_buffers::SceneBuffers;
use super::stage::{Stage, Workgroups};
use super::timing::{GpuTimer, Measure};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::{AccumulateRange, FilmPixel, WaveUniform};
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
pub use append::Append;
pub use compact::Scan;
use compact::Target;
pub use compute_passes::ComputePasses;
use path_state::{
    schedule_word as word, PathState, PoolLayout, LARGEST_BINDING_PER_PATH, QUEUE_COUNT, QUEUE_SHADOW,
};
pub use queue_order::QueueOrder;
pub use ray_sort::RaySort;
pub use refill::CompactStates;
pub use schedule::{Schedule, ScheduleStats};
use share_ledger::{ShareLedger, ShareWork};
use std::time::Instant;
pub use tail::Tail;

/// How queues are kept dense.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Compaction {
    /// No queues: every pass runs over the whole pool, dead lanes idle.
    Off,
    /// Each pass appends surviving paths to the next queue with an atomic counter.
    Atomic,
    /// Passes mark each path's next queue; a stable prefix-sum scan builds the queue.
    Scan,
}

/// How shading is dispatched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadePasses {
    /// One pass per material kind the scene uses.
    PerMaterial,
    /// One pass over every hit with a material switch (the megakernel's divergence).
    Single,
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WavefrontOptions {
    /// Paths in flight; `None`: the default from the adapter's limits.
    pub pool_size: Option<u32>,
    pub workgroup_size: u32,
    pub compaction: Compaction,
    pub shade: ShadePasses,
    pub schedule: Schedule,
    /// Regenerating: iterations recorded between read-backs of the schedule's counters (more:
    /// fewer host waits, up to this many idle iterations at the image's end; with the tail,
    /// every iteration once every sample has started).
    pub sync_every: u32,
    /// Regenerating: whether the last paths (of the image, and of the oldest chunks when the
    /// sample ring needs them back) are finished megakernel-style.
    pub tail: Tail,
    /// The live fraction of the pool below which the tail takes over.
    pub tail_threshold: f64,
    /// Regenerating: one-pool chunks in the sample ring (16 bytes a sample): how far refills
    /// may run ahead of the oldest chunk not yet in the film.
    pub chunk_pools: u32,
    /// How the scan compaction scans a workgroup.
    pub scan: Scan,
    /// How passes append paths to queues.
    pub append: Append,
    /// One compute pass per dispatch, or shared by consecutive dispatches (`--compute-passes`).
    pub compute_passes: ComputePasses,
    /// The order of the paths in each queue (slot order needs queues; `auto` takes it for
    /// regenerating jobs of several pools).
    pub queue_order: QueueOrder,
    /// Regenerating: refill only once at most this fraction of the pool is live (1: every
    /// iteration).
    pub refill_below: f64,
    /// Regenerating: compact the live states below the live count before each refill.
    pub compact_states: CompactStates,
    /// The key the ray queue is sorted by before each intersect (needs queues).
    pub ray_sort: RaySort,
}

impl Default for WavefrontOptions {
    fn default() -> Self {
        Self {
            pool_size: None,
            workgroup_size: 64,
            compaction: Compaction::Atomic,
            shade: ShadePasses::PerMaterial,
            schedule: Schedule::Waves,
            sync_every: schedule::DEFAULT_SYNC_EVERY,
            tail: Tail::Off,
            tail_threshold: tail::DEFAULT_THRESHOLD,
            chunk_pools: schedule::CHUNK_POOLS,
            scan: Scan::Auto,
            append: Append::Auto,
            compute_passes: ComputePasses::Shared,
            queue_order: QueueOrder::Auto,
            refill_below: refill::DEFAULT_REFILL_BELOW,
            compact_states: CompactStates::Off,
            ray_sort: RaySort::Off,
        }
    }
}

impl WavefrontOptions {
    /// `--schedule auto` made concrete for `adapter` ([`Schedule::Auto`]): `regenerate` with the
    /// megakernel tail on a GPU, `waves` on a software adapter. Other schedules stay as given.
    pub fn resolve(mut self, adapter: &crate::gpu::context::AdapterSummary) -> Self {
        if self.schedule == Schedule::Auto {
            if adapter.is_software() {
                self.schedule = Schedule::Waves;
            } else {
                self.schedule = Schedule::Regenerate;
                self.tail = Tail::Megakernel;
            }
        }
        self
    }
}

/// Default pool: about a million paths in flight (pbrt-v4's choice), less where limits say so.
pub const DEFAULT_POOL: u32 = 1 << 20;
/// Bounce histogram rows kept; deeper bounces are added to the last row.
pub const STATS_BOUNCES: u32 = path_state::MAX_STATS_BOUNCES as u32;

/// The largest pool the adapter can hold: every per-path buffer within one storage binding,
/// and one thread per path within one dispatch.
pub fn max_pool(ctx: &GpuContext, workgroup_size: u32) -> u32 {
    let s = &ctx.summary;
    let by_binding =
        s.max_storage_buffer_binding_size.min(s.max_buffer_size) / LARGEST_BINDING_PER_PATH.max(16);
    let by_threads =
        s.max_compute_workgroups_per_dimension as u64 * workgroup_size.min(path_state::SCAN_WG as u32) as u64;
    by_binding.min(by_threads).min(u32::MAX as u64) as u32
}

/// Per-bounce queue sizes summed over waves: `rays[b]` paths were intersected at bounce b,
/// `materials[k][b]` shaded with material kind k (all in `materials[0]` with one shade pass) and
/// `shadow[b]` shadow rays traced (empty without `--nee on`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct QueueHistogram {
    pub rays: Vec<u64>,
    pub materials: [Vec<u64>; 4],
    #[serde(default)]
    pub shadow: Vec<u64>,
}

/// The GPU objects every stage binds: scene (group 0), path state (group 1), SIMD counters
/// (group 2, with `--instrument`).
pub struct Bindings {
    pub scene: SceneBuffers,
    pub state: PathState,
    pub simd: Option<SimdCounters>,
    /// `--schedule regenerate` (the `REGENERATE` pipeline constant).
    pub regenerate: bool,
    /// Whether passes use the shader variants with subgroup-aggregated appends (`--append`).
    pub subgroup_append: bool,
    /// The runtime checks the passes' shaders are compiled with (`--shader-checks`).
    pub shader_checks: crate::gpu::shader_checks::ShaderChecks,
}

impl Bindings {
    /// A pass's own pipeline constants plus the scene's and the schedule's.
    pub fn constants(&self, own: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
        let mut c = self.scene.constants(own);
        c.push(("REGENERATE", self.regenerate as u32 as f64));
        c
    }

    pub fn layouts(&self) -> Vec<&wgpu::BindGroupLayout> {
        let mut l = vec![&self.scene.layout, &self.state.layout];
        l.extend(self.simd.as_ref().map(|s| &s.layout));
        l
    }

    /// Bind groups with the dynamic offset of the wave's dispatch parameters.
    pub fn groups(&self, offset: u32) -> Vec<(&wgpu::BindGroup, Vec<u32>)> {
        let mut g = vec![(&self.scene.bind_group, vec![]), (&self.state.bind_group, vec![offset])];
        g.extend(self.simd.as_ref().map(|s| (&s.bind_group, vec![])));
        g
    }
}

/// What every pass of a wave records into: the open encoder (and, with `--compute-passes
/// shared`, the open compute pass), the timer, the bindings and the wave's dispatch parameters.
pub struct WaveRecorder<'a> {
    /// The compute pass consecutive dispatches share (`--compute-passes shared`, without per-pass
    /// timestamps); ended before anything else is recorded into `enc`.
    pass: Option<wgpu::ComputePass<'static>>,
    /// Whether dispatches share passes.
    shared: bool,
    enc: wgpu::CommandEncoder,
    pub timer: &'a mut GpuTimer,
    pub b: &'a Bindings,
    /// Dynamic offset of the wave's `Dispatch` parameters.
    pub offset: u32,
    /// Paths in this wave.
    pub paths: u32,
    /// Whether passes are timed per bounce (waves) or only per label (regenerating: an
    /// iteration holds paths at every bounce).
    pub per_bounce: bool,
    /// Passes recorded (compute dispatches, empty ones included).
    pub dispatches: u64,
    /// Compute passes opened: `dispatches` with a pass per dispatch, fewer when they share.
    pub compute_passes: u64,
}

impl WaveRecorder<'_> {
    /// Records `stage` as a timed pass with the wave's first `groups` bind groups.
    pub fn record(&mut self, stage: &Stage, bounce: Option<u32>, groups: usize, workgroups: Workgroups<'_>) {
        self.record_with(stage, bounce, groups, None, workgroups);
    }

    /// [`Self::record`], with `extra` bound after the first `groups` bind groups.
    pub fn record_with(
        &mut self,
        stage: &Stage,
        bounce: Option<u32>,
        groups: usize,
        extra: Option<(&wgpu::BindGroup, Vec<u32>)>,
        workgroups: Workgroups<'_>,
    ) {
        let mut g = self.b.groups(self.offset);
        g.truncate(groups);
        g.extend(extra);
        let bounce = bounce.filter(|_| self.per_bounce);
        self.dispatches += 1;
        if !self.shared {
            stage.record(&mut self.enc, self.timer, bounce, &g, workgroups);
            self.compute_passes += 1;
            return;
        }
        // Counted under its label (there are no timestamps to write: `shared` is off with them).
        let writes = self.timer.pass_at(stage.label, bounce);
        debug_assert!(writes.is_none(), "shared compute passes without per-pass timestamps only");
        if self.pass.is_none() {
            let pass = self.enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("wavefront (shared)"),
                timestamp_writes: None,
            });
            self.pass = Some(pass.forget_lifetime());
            self.compute_passes += 1;
        }
        stage.dispatch(self.pass.as_mut().expect("opened above"), &g, workgroups);
    }

    /// The encoder, for copies and passes of other recorders: ends the shared compute pass.
    pub fn encoder(&mut self) -> (&mut wgpu::CommandEncoder, &mut GpuTimer) {
        self.pass = None;
        (&mut self.enc, self.timer)
    }

    /// Submits what is recorded and opens a new encoder, without waiting where passes are not
    /// timed (their timestamps are read back per batch, so then it waits).
    pub fn submit(&mut self, ctx: &GpuContext) -> Result<()> {
        if self.timer.times_passes() {
            return self.submit_and_wait(ctx);
        }
        self.pass = None;
        let enc = std::mem::replace(&mut self.enc, ctx.device.create_command_encoder(&Default::default()));
        self.timer.submit(ctx, enc)
    }

    /// Submits what is recorded, waits for it (adding its pass times) and opens a new encoder.
    pub fn submit_and_wait(&mut self, ctx: &GpuContext) -> Result<()> {
        self.pass = None;
        let enc = std::mem::replace(&mut self.enc, ctx.device.create_command_encoder(&Default::default()));
        self.timer.submit_batch(ctx, enc)
    }
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

/// The passes of a render, recorded per share and per iteration.
struct Stages {
    generate: generate::Generate,
    queue_setup: queue_setup::QueueSetup,
    intersect: intersect::Intersect,
    shade: shade::Shade,
    /// The scan passes: after intersect with the scan method, after shade with it or in
    /// slot-depth order.
    compact: Option<compact::Compact>,
    /// Slot order with the atomic method: the sweep after shade.
    slot_sweep: Option<slot_sweep::SlotSweep>,
    scan_materials: bool,
    shadow: Option<shadow::Shadow>,
    tail: Option<tail::TailPass>,
    /// `--compact-states on`: before each refill.
    compact_states: Option<compact_states::CompactStatesPasses>,
    /// `--ray-sort`: between queue_setup_intersect and intersect.
    ray_sort: Option<ray_sort::RaySortPasses>,
    regenerate: bool,
}

impl Stages {
    /// One iteration: a bounce of every path in waves; when regenerating, a refill (while the
    /// share has samples left to start) and then a bounce of every path in the pool, whatever
    /// its depth.
    fn record_iteration(&self, wave: &mut WaveRecorder<'_>, i: u32, refill: bool) {
        if self.regenerate && refill {
            self.queue_setup.record_regenerate(wave, i);
            if let Some(c) = &self.compact_states {
                c.record(wave, &self.queue_setup, i);
            }
            self.generate.record_refill(wave, i);
        }
        self.queue_setup.record_intersect(wave, i);
        if let Some(sort) = &self.ray_sort {
            sort.record(wave, i);
        }
        self.intersect.record(wave, i);
        if let Some(compact) = self.compact.as_ref().filter(|_| self.scan_materials) {
            compact.record(wave, i, Target::MaterialQueues);
        }
        self.queue_setup.record_shade(wave, i);
        self.shade.record(wave, i);
        if let Some(compact) = &self.compact {
            compact.record(wave, i, Target::NextRayQueue);
        }
        if let Some(sweep) = &self.slot_sweep {
            sweep.record(wave, i);
        }
        if let Some(shadow) = &self.shadow {
            self.queue_setup.record_shadow(wave, i);
            shadow.record(wave, i);
        }
    }

    /// Passes one iteration records, to keep each submission within the timer's capacity.
    fn per_iteration(&self) -> usize {
        3 + self.shade.passes()
            + if self.compact.is_some() { 3 } else { 0 }
            + if self.slot_sweep.is_some() { 1 } else { 0 }
            + if self.scan_materials { 3 } else { 0 }
            + if self.shadow.is_some() { 2 } else { 0 }
            + if self.regenerate { 2 } else { 0 }
            + if self.compact_states.is_some() { 3 } else { 0 }
            + if self.ray_sort.is_some() { 3 } else { 0 }
    }
}

/// What drives every share of a render: its passes, bindings and options. One method per
/// schedule records a share's iterations and returns how many it recorded.
struct Drive<'a> {
    ctx: &'a GpuContext,
    stages: &'a Stages,
    b: &'a Bindings,
    accumulate: &'a Accumulate,
    opts: &'a WavefrontOptions,
    max_depth: u32,
    pool: u32,
    /// Passes one iteration records (a submission's timestamp capacity).
    per_iteration: usize,
}

impl Drive<'_> {
    /// Waves: one iteration per bounce, the wave's paths all starting together.
    fn waves(&self, wave: &mut WaveRecorder<'_>) -> Result<u32> {
        for bounce in 0..self.max_depth {
            if wave.timer.remaining() < self.per_iteration + 1 {
                wave.submit_and_wait(self.ctx)?;
            }
            self.stages.record_iteration(wave, bounce, false);
        }
        Ok(self.max_depth)
    }

    /// Regenerating: iterations until every sample of the share (`r`) is in the film, the host
    /// reading the schedule's counters through `check` at each check; `progress` gets the
    /// share's finished samples.
    fn regenerate(
        &self,
        wave: &mut WaveRecorder<'_>,
        r: &schedule::Ring,
        check: &Staging,
        pixel_count: u32,
        stats: &mut ScheduleStats,
        progress: &dyn Fn(u64),
    ) -> Result<u32> {
        let paths = r.paths;
        // Iterate until every sample of the share is in the film, reading the counters
        // back only every `sync_every` iterations; after each read, add the chunks that
        // are complete (with the tail, finish the oldest ones' last paths first where the
        // ring needs them back) and move the refills' limit on.
        self.b.state.write_schedule_word(self.ctx, word::FILL_LIMIT, r.fill_limit(0));
        self.b.state.write_schedule_word(self.ctx, word::TAIL_BOUND, 0);
        let mut i = 0;
        let mut stall = schedule::Progress::new(paths, self.max_depth, self.opts.sync_every);
        // Once a check finds every sample started, the refill passes would be empty.
        let mut refill = true;
        // The first chunk not yet in the film, and the samples started at the last check.
        let (mut oldest, mut started_before) = (0, 0);
        // Whether the first refill starts every sample (it starts a pool of them, up to
        // the ring's end); later, a check says so by clearing `refill`.
        let one_refill = paths <= self.pool.min(r.fill_limit(0));
        loop {
            for _ in 0..self.opts.sync_every {
                if wave.timer.remaining() < self.per_iteration + 1 {
                    wave.submit_and_wait(self.ctx)?;
                }
                self.stages.record_iteration(wave, i, refill);
                i += 1;
                // With the tail, once every sample has started the host checks after
                // every iteration: the tail starts in the iteration it is due, and no
                // idle iteration follows it.
                if self.stages.tail.is_some() && (one_refill || !refill) {
                    break;
                }
            }
            schedule::ChunkCounters::copy(wave.encoder().0, check, &self.b.state, r);
            wave.submit_and_wait(self.ctx)?;
            let c = schedule::ChunkCounters::read(self.ctx, check, r, oldest)?;
            progress(c.finished as u64);
            stall.check(c.finished, i)?;
            let threshold = self.stages.tail.as_ref().map(|_| self.opts.tail_threshold);
            let decision = schedule::Decision::after(r, &c, oldest, started_before, self.pool, threshold);
            refill = decision.refill;
            if let (Some(tail), Some(bound)) = (&self.stages.tail, decision.tail_bound) {
                let left = |k: u32| r.len(k) - c.ring[(k % r.ring) as usize];
                stats.add_tail((decision.complete..bound).map(left).sum());
                self.b.state.write_schedule_word(self.ctx, word::TAIL_BOUND, r.end(bound - 1));
                self.stages.queue_setup.record_tail(wave, i);
                tail.record(wave);
            }
            let added = decision.added;
            started_before = c.started;
            if added > oldest {
                let first = oldest * r.chunk;
                let count = r.end(added - 1) - first;
                let range = AccumulateRange { first, count, ring: r.samples(), pad: 0 };
                let offset = wave.offset;
                let (enc, timer) = wave.encoder();
                self.accumulate.record_range(self.ctx, enc, timer, offset, pixel_count, range);
                wave.dispatches += 1;
                wave.compute_passes += 1;
                self.b.state.clear_ring_counters(wave.encoder().0, (oldest..added).map(|k| k % r.ring));
                oldest = added;
                self.b.state.write_schedule_word(self.ctx, word::FILL_LIMIT, r.fill_limit(oldest));
            }
            if oldest == r.chunks() {
                break Ok(i);
            }
            if c.finished == paths {
                let total = r.chunks();
                bail!(
                    "the regenerating wavefront finished every sample but added {oldest} of {total} chunks"
                );
            }
        }
    }
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
    let instrument = measure.instrument;
    let opts = &opts.resolve(&ctx.summary);
    settings.validate().map_err(anyhow::Error::msg)?;
    check_loop_limit(ctx, scene, settings)?;
    let wg = opts.workgroup_size;
    ctx.check_workgroup_size(wg)?;
    // A job smaller than the pool needs no more slots than samples: passes over the whole pool
    // (the regenerating schedule's start, compaction off) and its memory shrink with it.
    let pool = choose_pool(ctx, opts)?.min(u32::try_from(settings.sample_count()).unwrap_or(u32::MAX));
    schedule::check_sync_every(opts.sync_every)?;
    schedule::check_chunk_pools(opts.chunk_pools)?;
    tail::check_threshold(opts.tail_threshold)?;
    opts.queue_order.check(opts.compaction)?;
    refill::check(opts.refill_below, opts.compact_states, opts.schedule, opts.compaction)?;
    opts.ray_sort.check(opts.compaction)?;
    let queue_order = opts.queue_order.resolve(opts.schedule, opts.compaction, settings.sample_count(), pool);
    let subgroup_scan = opts.scan.uses_subgroups(ctx)?;
    let subgroup_append = opts.append.uses_subgroups(ctx)?;
    let regenerate = opts.schedule == Schedule::Regenerate;
    if opts.tail == Tail::Megakernel && !regenerate {
        bail!("--tail megakernel finishes regenerated paths: it needs --schedule regenerate");
    }
    if opts.chunk_pools != schedule::CHUNK_POOLS && !regenerate {
        bail!("--chunk-pools sizes the regenerating sample ring: it needs --schedule regenerate");
    }
    let start = Instant::now();

    let pixels = settings.width * settings.height;
    let shares = schedule::shares(opts.schedule, pixels, settings.spp, pool, settings.max_depth);
    let mut memory = MemoryLedger::default();
    let params = DispatchUniforms::new(ctx, &shares, &mut memory);
    let kinds = scene.material_kinds_used();
    let per_material = opts.shade == ShadePasses::PerMaterial;
    // Regenerating: every share's sample ring has the same chunks (one pool) and at most the
    // same number of them, so one ring buffer serves them all.
    let ring_budget = schedule::ring_budget(ctx, pool, opts.chunk_pools);
    let largest_share = shares.iter().map(|d| d.pixel_count * d.sample_count).max().unwrap_or(1);
    let ring = schedule::Ring::new(largest_share, pool, ring_budget);
    let wave = WaveUniform {
        compaction: opts.compaction as u32,
        per_material: per_material as u32,
        pool,
        shade_mask: if per_material { kinds.iter().fold(0, |m, k| m | 1 << k) } else { 1 },
        chunk: if regenerate { ring.chunk } else { 0 },
        ring: if regenerate { ring.ring } else { 0 },
        order: queue_order.word(),
        refill_live: refill::refill_live(opts.refill_below, pool),
        compact_states: (opts.compact_states == CompactStates::On) as u32,
        pad1: 0,
        pad2: 0,
    };
    let stats_bounces = if regenerate { 1 } else { settings.max_depth.min(STATS_BOUNCES) };
    let frame = scene.frame_uniform(camera, settings);
    let has_shadow_pass = settings.nee && !scene.lights.is_empty();
    // The scan passes: the scan method's, or the depth key's over the pool after shade; slot
    // order with atomic appends sweeps the pool instead (slot_sweep.wgsl).
    let uses_sweep = queue_order == QueueOrder::Slot && opts.compaction == Compaction::Atomic;
    let uses_scan = opts.compaction == Compaction::Scan || (queue_order.is_slot() && !uses_sweep);
    let layout = PoolLayout {
        targets: uses_scan || uses_sweep,
        scan: uses_scan,
        shadow: has_shadow_pass,
        ring_samples: regenerate.then_some(ring.samples() as u64),
    };
    let b = Bindings {
        scene: SceneBuffers::new(ctx, scene, &frame, settings, measure.specialize, &mut memory)?,
        state: PathState::new(ctx, pool, wave, &params, stats_bounces, layout, &mut memory)?,
        simd: instrument.then(|| SimdCounters::new(ctx, &mut memory)).transpose()?,
        regenerate,
        subgroup_append,
        shader_checks: measure.shader_checks,
    };
    let film_bytes = pixels as u64 * std::mem::size_of::<FilmPixel>() as u64;
    let film = memory
        .track(MemoryCategory::Film, storage_zeroed(ctx, "film", film_bytes, wgpu::BufferUsages::COPY_SRC)?);

    let shade_kinds = per_material.then_some(kinds.as_slice());
    let stages = Stages {
        generate: generate::Generate::new(ctx, &b, opts.schedule, pool, wg, instrument)?,
        queue_setup: queue_setup::QueueSetup::new(ctx, &b, wg)?,
        intersect: intersect::Intersect::new(ctx, &b, wg, instrument)?,
        shade: shade::Shade::new(ctx, &b, shade_kinds, wg, instrument)?,
        compact: uses_scan.then(|| compact::Compact::new(ctx, &b, subgroup_scan)).transpose()?,
        slot_sweep: uses_sweep.then(|| slot_sweep::SlotSweep::new(ctx, &b)).transpose()?,
        shadow: has_shadow_pass.then(|| shadow::Shadow::new(ctx, &b, wg, instrument)).transpose()?,
        tail: (opts.tail == Tail::Megakernel)
            .then(|| tail::TailPass::new(ctx, &b, wg, instrument))
            .transpose()?,
        compact_states: (opts.compact_states == CompactStates::On)
            .then(|| compact_states::CompactStatesPasses::new(ctx, &b, wg))
            .transpose()?,
        ray_sort: (opts.ray_sort != RaySort::Off)
            .then(|| ray_sort::RaySortPasses::new(ctx, &b, wg, opts.ray_sort, &mut memory))
            .transpose()?,
        scan_materials: opts.compaction == Compaction::Scan,
        regenerate,
    };
    let samples = if regenerate { &b.state.samples } else { &b.state.radiance };
    let accumulate = Accumulate::new(ctx, samples, &film, &params, regenerate, measure.shader_checks)?;

    // Regenerating: the staging buffer every check reads the schedule's counters through.
    let check_staging = regenerate.then(|| {
        let bytes = schedule::ChunkCounters::bytes(&ring);
        memory.add(MemoryCategory::Counters, bytes);
        Staging::new(ctx, "schedule counters read-back", bytes)
    });
    let per_iteration = stages.per_iteration();
    let mut timer = GpuTimer::new(ctx, measure.timing, measure.preheat_seconds, &mut memory);
    // Per-pass timestamps need a pass per dispatch.
    let shared_passes = opts.compute_passes == ComputePasses::Shared && !timer.times_passes();
    let mut histogram = (opts.compaction != Compaction::Off && !regenerate).then(QueueHistogram::default);
    let mut stats = ScheduleStats::new(opts.schedule, opts.sync_every, pool);
    stats.subgroup_scan = uses_scan.then_some(subgroup_scan);
    stats.subgroup_append = subgroup_append;
    stats.slot_order = queue_order.is_slot();
    stats.depth_key = queue_order == QueueOrder::SlotDepth;
    stats.ray_sort = Some(opts.ray_sort.name());
    if regenerate {
        stats.refill_below = Some(opts.refill_below);
        stats.compact_states = Some(opts.compact_states == CompactStates::On);
    }
    // Path samples the GPU has finished (waves are submitted without waiting for them).
    let finished = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let mut ledger = (!regenerate).then(|| ShareLedger::new(ctx, &b.state, &mut memory));
    let mut compute_passes = 0u64;
    let drive = Drive {
        ctx,
        stages: &stages,
        b: &b,
        accumulate: &accumulate,
        opts,
        max_depth: settings.max_depth,
        pool,
        per_iteration,
    };
    for (w, d) in shares.iter().enumerate() {
        let paths = d.pixel_count * d.sample_count;
        // Regenerating: this share's sample ring (the render's chunk and ring sizes).
        let r = schedule::Ring { paths, ..ring };
        let enc = ctx.device.create_command_encoder(&Default::default());
        let mut wave = WaveRecorder {
            pass: None,
            shared: shared_passes,
            enc,
            timer: &mut timer,
            b: &b,
            offset: params.offset(w),
            paths,
            per_bounce: !regenerate,
            dispatches: 0,
            compute_passes: 0,
        };

        stages.generate.record_start(&mut wave);
        let iterations = match opts.schedule {
            Schedule::Waves => drive.waves(&mut wave)?,
            Schedule::Auto => unreachable!("render() resolves --schedule auto first"),
            Schedule::Regenerate => {
                let check = check_staging.as_ref().expect("regenerating renders make a staging buffer");
                let done = finished.load(std::sync::atomic::Ordering::Relaxed);
                drive
                    .regenerate(&mut wave, &r, check, d.pixel_count, &mut stats, &|f| on_progress(done + f))?
            }
        };
        if regenerate {
            wave.submit_and_wait(ctx)?;
            stats.add_share(ctx, &b.state, r.chunks(), iterations, wave.dispatches)?;
        } else {
            let offset = wave.offset;
            let (enc, timer) = wave.encoder();
            accumulate.record(enc, timer, offset, d.pixel_count);
            wave.dispatches += 1;
            wave.compute_passes += 1;
            // Per wave, so the GPU's u32 counters never overflow on long renders; copied on the
            // GPU, so the host goes on to the next wave without waiting for this one.
            let work = ShareWork { units: 1, iterations, dispatches: wave.dispatches };
            let ledger = ledger.as_mut().expect("waves keep a share ledger");
            ledger.record(wave.encoder().0, &b.state, work);
            if w + 1 == shares.len() || ledger.is_full() {
                wave.submit_and_wait(ctx)?;
                ledger.drain(ctx, &mut stats, histogram.as_mut())?;
            } else {
                wave.submit(ctx)?;
            }
        }
        compute_passes += wave.compute_passes;
        let count = finished.clone();
        ctx.queue.on_submitted_work_done(move || {
            count.fetch_add(paths as u64, std::sync::atomic::Ordering::Relaxed);
        });
        // Runs the callbacks of whatever has finished, without waiting.
        ctx.device.poll(wgpu::PollType::Poll).map_err(|e| anyhow::anyhow!("polling the GPU failed: {e}"))?;
        on_progress(finished.load(std::sync::atomic::Ordering::Relaxed));
    }

    if let Some(h) = &mut histogram {
        h.trim();
    }
    memory.transient(film_bytes);
    let data: Vec<FilmPixel> = read_back(ctx, &film, film_bytes)?;
    let film = Film::from_gpu(settings.width, settings.height, settings.spp, &data);
    let simd = b.simd.as_ref().map(|s| s.read(ctx)).transpose()?;
    let coherence = b.simd.as_ref().map(|s| s.read_coherence(ctx)).transpose()?;
    let failures = b.scene.read_failures(ctx)?;
    Ok(WavefrontRender {
        render: GpuRender {
            film,
            timings: timer.into_timings(),
            dispatches: stats.dispatches,
            compute_passes,
            empty_dispatches: Some(stats.empty_dispatches),
            wall_seconds: start.elapsed().as_secs_f64(),
            simd,
            bytes_per_path: layout.bytes_per_path(),
            memory: memory.summary(),
            failures,
            threads: None,
        },
        pool,
        histogram,
        schedule: stats,
        coherence,
        resolved: WavefrontOptions {
            pool_size: Some(pool),
            queue_order,
            scan: if subgroup_scan { Scan::Subgroup } else { Scan::Workgroup },
            append: if subgroup_append { Append::Subgroup } else { Append::Lane },
            compute_passes: if shared_passes { ComputePasses::Shared } else { ComputePasses::PerDispatch },
            ..*opts
        },
    })
}

fn choose_pool(ctx: &GpuContext, opts: &WavefrontOptions) -> Result<u32> {
    let max = max_pool(ctx, opts.workgroup_size);
    if max == 0 {
        bail!("{} cannot hold even one path's state in its storage bindings", ctx.summary.name);
    }
    Ok(match opts.pool_size {
        Some(0) => bail!("--pool-size must be at least 1"),
        Some(p) if p > max => {
            eprintln!(
                "notice: pool of {p} paths does not fit {} ({LARGEST_BINDING_PER_PATH} bytes per path in \
                 its largest buffer, {} per binding); using {max}",
                ctx.summary.name,
                super::buffers::human_bytes(ctx.summary.max_storage_buffer_binding_size)
            );
            max
        }
        Some(p) => p,
        None => DEFAULT_POOL.min(max),
    })
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
            *v += row(b, 2 + k);
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
