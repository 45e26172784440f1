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
//!                                           (--nee on) diffuse hits → shadow queue
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
//! sample order under both schedules, so they give bit-identical films.

pub mod append;
pub mod compact;
pub mod compact_states;
pub mod generate;
pub mod intersect;
pub mod intersect_registers;
pub mod path_state;
pub mod pool;
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
pub mod traffic;

use super::accumulate::Accumulate;
use super::buffers::{self, read_back, storage_zeroed, Staging};
use super::context::GpuContext;
use super::dispatch_plan::DispatchUniforms;
use super::gpu_render::GpuRender;
use super::instrument::{Coherence, SimdCounters};
use super::loop_limit::check_loop_limit;
use super::memory::{MemoryCategory, MemoryLedger};
use super::scene_buffers::SceneBuffers;
use super::shaders::Hook;
use super::stage::{Stage, Workgroups};
use super::timing::{GpuTimer, Measure};
use crate::camera::CameraFrame;
use crate::film::Film;
use crate::layout::{FilmPixel, WaveUniform};
use crate::options::Named;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
// The options live in `crate::options`; the wavefront's are re-exported where it is built.
pub use crate::options::{
    Append, CompactStates, Compaction, ComputePasses, Launch, QueueOrder, RaySort, ResolvedWavefront,
    RunSchedule, Scan, Schedule, ShadePasses, Tail, WavefrontOptions, BATCHES_IN_FLIGHT,
    MAX_BATCHES_IN_FLIGHT,
};
use compact::Target;
use path_state::{schedule_word as word, PathState, PoolLayout, QUEUE_COUNT, QUEUE_SHADOW};
pub use pool::{max_pool, DEFAULT_POOL};
pub use schedule::ScheduleStats;
use share_ledger::{ShareLedger, ShareWork};
use std::time::Instant;

/// Bounce histogram rows kept; deeper bounces are added to the last row.
pub const STATS_BOUNCES: u32 = path_state::MAX_STATS_BOUNCES as u32;

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
    pub shader_checks: crate::options::ShaderChecks,
}

impl Bindings {
    /// A pass's own pipeline constants plus the scene's and the schedule's.
    pub fn constants(&self, own: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
        let mut c = self.scene.constants(own);
        c.push(("REGENERATE", self.regenerate as u32 as f64));
        c
    }

    /// The shader variant an appending pass takes: instrumented or not, and its appends.
    pub fn hooks(&self, instrument: bool) -> [(Hook, bool); 2] {
        [(Hook::Instrument, instrument), (Hook::AppendSubgroup, self.subgroup_append)]
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
    /// `--launch pool`: the workgroups that cover the pool's slots (a wave's paths), which the
    /// passes consuming a queue are launched with instead of their indirect arguments.
    pub pool_launch: Option<u32>,
}

impl<'a> WaveRecorder<'a> {
    /// The launch of a pass that consumes a queue: at the pool's size (`--launch pool`), or the
    /// indirect arguments a setup pass wrote at argument slot `slot`.
    pub fn consumer(&self, slot: u64) -> Workgroups<'a> {
        let b: &'a Bindings = self.b;
        match self.pool_launch {
            Some(groups) => Workgroups::Direct(groups),
            None => Workgroups::Indirect(&b.state.indirect, slot * 12),
        }
    }
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
        let b = self.b;
        let mut g = b.groups(self.offset);
        g.truncate(groups);
        g.extend(extra);
        self.record_groups(stage, bounce, &g, workgroups);
    }

    /// Records `stage` as a timed pass with the bind groups `g` (group i: `g[i]`).
    pub fn record_groups(
        &mut self,
        stage: &Stage,
        bounce: Option<u32>,
        g: &[(&wgpu::BindGroup, Vec<u32>)],
        workgroups: Workgroups<'_>,
    ) {
        let bounce = bounce.filter(|_| self.per_bounce);
        self.dispatches += 1;
        if !self.shared {
            stage.record(&mut self.enc, self.timer, bounce, g, workgroups);
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
        stage.dispatch(self.pass.as_mut().expect("opened above"), g, workgroups);
    }

    /// The encoder, for copies and passes of other recorders: ends the shared compute pass.
    pub fn encoder(&mut self) -> (&mut wgpu::CommandEncoder, &mut GpuTimer) {
        self.pass = None;
        (&mut self.enc, self.timer)
    }

    /// Submits what is recorded and opens a new encoder, without waiting where passes are not
    /// timed (their timestamps are read back per batch, so then it waits).
    pub fn submit(&mut self, ctx: &GpuContext) -> Result<()> {
        self.submit_ahead(ctx).map(|_| ())
    }

    /// [`Self::submit`], giving the submission's index where it did not wait (None: per-pass
    /// timestamps, read back per batch, so it waited).
    pub fn submit_ahead(&mut self, ctx: &GpuContext) -> Result<Option<wgpu::SubmissionIndex>> {
        if self.timer.times_passes() {
            self.submit_and_wait(ctx)?;
            return Ok(None);
        }
        self.pass = None;
        let enc = std::mem::replace(&mut self.enc, ctx.device.create_command_encoder(&Default::default()));
        self.timer.submit(ctx, enc).map(Some)
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
    /// `decide` (regenerate): the iteration ends with the schedule's decision pass (with NEE
    /// folded into queue_setup_shadow); the caller records the passes it sizes after.
    fn record_iteration(&self, wave: &mut WaveRecorder<'_>, i: u32, refill: bool, decide: bool) {
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
            if decide {
                self.queue_setup.record_shadow_decide(wave, i);
            } else {
                self.queue_setup.record_shadow(wave, i);
            }
            shadow.record(wave, i);
        } else if decide {
            self.queue_setup.record_decide(wave, i);
        }
    }

    /// Passes one iteration records, to keep each submission within the timer's capacity.
    fn per_iteration(&self) -> usize {
        3 + self.shade.passes()
            + if self.compact.is_some() { 3 } else { 0 }
            + if self.slot_sweep.is_some() { 1 } else { 0 }
            + if self.scan_materials { 3 } else { 0 }
            + if self.shadow.is_some() { 2 } else { 0 }
            // The refill's two passes, and the decision pass with the tail and accumulate_range.
            + if self.regenerate { 5 } else { 0 }
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
            self.stages.record_iteration(wave, bounce, false, false);
        }
        Ok(self.max_depth)
    }

    /// Regenerating: iterations until every sample of the share (`r`) is in the film. The GPU
    /// decides after each check (queue_setup.wgsl's `schedule_decide`, recorded by
    /// [`Self::record_decided`]): the host records batches of `--sync-every` iterations and
    /// submits them without waiting, each batch's counters copied into the next of the `staging`
    /// ring, whose mapping it polls; it stops recording once a read-back says the share is done.
    /// At `--batches-in-flight` batches it waits for the oldest one's read-back, newer batches
    /// queued behind it (a throttle; with one batch, a blocking read). `progress` gets the share's finished samples. Returns the
    /// iterations the share ran (those recorded after its end are counted as speculative).
    fn regenerate(
        &self,
        wave: &mut WaveRecorder<'_>,
        r: &schedule::Ring,
        staging: &[Staging],
        stats: &mut ScheduleStats,
        progress: &dyn Fn(u64),
    ) -> Result<u32> {
        let (ctx, state) = (self.ctx, &self.b.state);
        let tail = self.stages.tail.is_some();
        let sync_every = self.opts.sync_every;
        // The decision pass's knobs and the refills' first limit; its own words start at zero
        // (the buffer's creation, or the clear after the last share).
        state.write_schedule_word(ctx, word::FILL_LIMIT, r.fill_limit(0));
        state.write_schedule_word(ctx, word::TAIL_BOUND, 0);
        state.write_schedule_word(ctx, word::SYNC_EVERY, sync_every);
        state.write_schedule_word(ctx, word::TAIL_ON, tail as u32);
        // `Decision::after` compares a path count with threshold × pool: for whole counts, the
        // same as comparing with its floor.
        let max_live = (self.opts.tail_threshold * self.pool as f64).floor() as u32;
        state.write_schedule_word(ctx, word::TAIL_MAX_LIVE, max_live);
        let mut stall = schedule::Progress::new(r.paths, self.max_depth, sync_every);
        // Whether the first refill starts every sample (it starts a pool of them, up to the
        // ring's end): then later iterations record no refill passes.
        let one_refill = r.paths <= self.pool.min(r.fill_limit(0));
        let bytes = schedule::ChunkCounters::bytes(r);
        let mut pending = std::collections::VecDeque::new();
        let mut next_staging = 0;
        // Iterations recorded, and the dispatches and compute passes recorded up to each one's
        // end (its decision passes included): the share's own counts once the GPU says how many
        // it ran.
        let mut recorded = 0u32;
        let mut dispatches_at = Vec::new();
        let mut ran = None;
        // Reads a batch's counters back once mapped: Some(iterations) when the share is done.
        let mut read = |req: buffers::MapRequest, k: usize| -> Result<Option<u32>> {
            let words: Vec<u32> = staging[k].take(&req)?;
            let (c, back) = schedule::ChunkCounters::parse(&words, r);
            if back.failed {
                bail!(
                    "the regenerating wavefront finished every sample but added {} of {} chunks",
                    back.oldest,
                    r.chunks()
                );
            }
            progress(c.finished.min(r.paths) as u64);
            if back.done {
                return Ok(Some(back.iteration));
            }
            stall.check(c.finished, back.iteration)?;
            Ok(None)
        };
        while ran.is_none() {
            if pending.len() == staging.len() {
                let (req, k, index): (buffers::MapRequest, usize, Option<wgpu::SubmissionIndex>) =
                    pending.pop_front().expect("a batch in flight");
                if !req.is_ready() {
                    // Newer batches queued behind this one keep the GPU busy meanwhile.
                    let idle = pending.is_empty();
                    if idle {
                        stats.blocking_reads += 1;
                    } else {
                        stats.throttles += 1;
                    }
                    req.wait(ctx, index)?;
                    // A blocking read counts with the frame's waits, its idle GPU as a host gap.
                    if idle {
                        wave.timer.note_blocking_wait();
                    }
                }
                ran = read(req, k)?;
                continue;
            }
            for _ in 0..sync_every {
                if wave.timer.remaining() < self.per_iteration + 1 {
                    wave.submit_and_wait(ctx)?;
                }
                // With the tail the GPU may check after any iteration (every one once every
                // sample has started), so it decides after each; else after every batch.
                let decide = tail || (recorded + 1).is_multiple_of(sync_every);
                self.stages.record_iteration(wave, recorded, recorded == 0 || !one_refill, decide);
                if decide {
                    self.record_decided(wave);
                }
                recorded += 1;
                dispatches_at.push((wave.dispatches, wave.compute_passes));
            }
            let k = next_staging;
            next_staging = (k + 1) % staging.len();
            staging[k].copy(wave.encoder().0, &state.counters, bytes);
            let index = wave.submit_ahead(ctx)?;
            pending.push_back((staging[k].request(bytes), k, index));
            // Completes the mappings of whatever has finished, without waiting.
            ctx.device
                .poll(wgpu::PollType::Poll)
                .map_err(|e| anyhow::anyhow!("polling the GPU failed: {e}"))?;
            while ran.is_none() && pending.front().is_some_and(|p| p.0.is_ready()) {
                let (req, k, _) = pending.pop_front().expect("checked above");
                ran = read(req, k)?;
            }
        }
        // The share's end: wait for the iterations queued past it, then release their read-backs.
        wave.submit_and_wait(ctx)?;
        for (req, k, _) in pending {
            staging[k].discard(&req);
        }
        let ran = ran.expect("the loop ends once a read-back says the share is done");
        if ran == 0 || ran > recorded {
            bail!("the regenerating wavefront's GPU counted {ran} iterations of the {recorded} recorded");
        }
        stats.speculative_iterations += (recorded - ran) as u64;
        let (own, own_passes) = dispatches_at[ran as usize - 1];
        stats.speculative_dispatches += wave.dispatches - own;
        wave.dispatches = own;
        wave.compute_passes = own_passes;
        Ok(ran)
    }

    /// (regenerate) After an iteration that ends with the decision pass: the passes it sizes
    /// (zero workgroups unless it decided to run them): the tail, and the film's new chunks.
    fn record_decided(&self, wave: &mut WaveRecorder<'_>) {
        if let Some(tail) = &self.stages.tail {
            tail.record(wave);
        }
        let (stage, groups) = self.accumulate.range_pass(wave.offset);
        let args = Workgroups::Indirect(&self.b.state.indirect, path_state::ARGS_ACCUMULATE * 12);
        wave.record_groups(stage, None, &groups, args);
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
    let ResolvedWavefront { options: ref opts, schedule } = opts.resolve(ctx.summary.is_software());
    crate::options::check_wavefront(opts)?;
    settings.validate().map_err(anyhow::Error::msg)?;
    check_loop_limit(ctx, scene, settings)?;
    let wg = opts.workgroup_size;
    ctx.check_workgroup_size(wg)?;
    // A job smaller than the pool needs no more slots than samples: passes over the whole pool
    // (the regenerating schedule's start, compaction off) and its memory shrink with it.
    let pool = pool::choose(ctx, opts)?.min(u32::try_from(settings.sample_count()).unwrap_or(u32::MAX));
    let queue_order = opts.queue_order.resolve(opts.schedule, opts.compaction, settings.sample_count(), pool);
    let subgroup_scan = opts.scan.uses_subgroups(ctx)?;
    let subgroup_append = opts.append.uses_subgroups(ctx)?;
    let regenerate = schedule == RunSchedule::Regenerate;
    let start = Instant::now();

    let pixels = settings.width * settings.height;
    let shares = schedule::shares(schedule, pixels, settings.spp, pool, settings.max_depth);
    let mut memory = MemoryLedger::default();
    let params = DispatchUniforms::new(ctx, &shares, &mut memory);
    let per_texture = opts.shade == ShadePasses::PerTexture;
    // Per-texture: the patterns' passes, and the material kinds' passes for what is left.
    let (kinds, patterns) =
        if per_texture { scene.shade_classes() } else { (scene.material_kinds_used(), vec![]) };
    // Regenerating: every share's sample ring has the same chunks (one pool) and at most the
    // same number of them, so one ring buffer serves them all.
    let ring_budget = schedule::ring_budget(ctx, pool, opts.chunk_pools);
    let largest_share = shares.iter().map(|d| d.pixel_count * d.sample_count).max().unwrap_or(1);
    let ring = schedule::Ring::new(largest_share, pool, ring_budget);
    // Camera rays made where they are used (wavefront/shared/path_camera.wgsl) need queues (a pass over
    // the whole pool tells live slots by their stored direction) and no ray sort (whose keys
    // read the stored ray).
    let camera_in_place = opts.compaction != Compaction::Off && opts.ray_sort == RaySort::Off;
    let wave = WaveUniform {
        compaction: opts.compaction as u32,
        per_material: match opts.shade {
            ShadePasses::Single => 0,
            ShadePasses::PerMaterial => 1,
            ShadePasses::PerTexture => 2,
            ShadePasses::Sorted => 3,
        },
        pool,
        // Bits 0–3: the material kinds' passes; 4–11: the patterns'; none for the sorted pass
        // (queue_setup_shade counts it itself).
        shade_mask: match opts.shade {
            ShadePasses::Single => 1,
            ShadePasses::Sorted => 0,
            ShadePasses::PerMaterial | ShadePasses::PerTexture => {
                kinds.iter().fold(0, |m, k| m | 1 << k) | patterns.iter().fold(0, |m, p| m | 1 << (4 + p))
            }
        },
        chunk: if regenerate { ring.chunk } else { 0 },
        ring: if regenerate { ring.ring } else { 0 },
        order: queue_order.word(),
        refill_live: refill::refill_live(opts.refill_below, pool),
        compact_states: (opts.compact_states == CompactStates::On) as u32,
        camera_in_place: camera_in_place as u32,
        launch_pool: (opts.launch == Launch::Pool) as u32,
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
        pattern_queues: per_texture,
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

    let samples = if regenerate { &b.state.samples } else { &b.state.radiance };
    let accumulate = Accumulate::new(ctx, samples, &film, &params, regenerate, measure.shader_checks)?;
    let stages = Stages {
        generate: generate::Generate::new(ctx, &b, schedule, pool, wg, instrument)?,
        queue_setup: queue_setup::QueueSetup::new(
            ctx,
            &b,
            wg,
            regenerate.then(|| accumulate.range_buffer()),
        )?,
        intersect: intersect::Intersect::new(ctx, &b, wg, instrument)?,
        shade: shade::Shade::new(ctx, &b, opts.shade, &kinds, &patterns, wg, instrument)?,
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

    // Regenerating: the ring of staging buffers the batches in flight read the schedule's
    // counters back through.
    let staging: Vec<Staging> = (0..if regenerate { opts.batches_in_flight } else { 0 })
        .map(|_| {
            let bytes = schedule::ChunkCounters::bytes(&ring);
            memory.add(MemoryCategory::Counters, bytes);
            Staging::new(ctx, "schedule counters read-back", bytes)
        })
        .collect();
    let per_iteration = stages.per_iteration();
    let mut timer = GpuTimer::new(ctx, measure.timing, measure.preheat_seconds, &mut memory);
    // Per-pass timestamps need a pass per dispatch.
    let shared_passes = opts.compute_passes == ComputePasses::Shared && !timer.times_passes();
    let mut histogram = (opts.compaction != Compaction::Off && !regenerate).then(QueueHistogram::default);
    let mut stats = ScheduleStats::new(schedule.into(), opts.sync_every, pool);
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
            pool_launch: (opts.launch == Launch::Pool)
                .then(|| (if regenerate { pool } else { paths }).div_ceil(wg)),
        };

        stages.generate.record_start(&mut wave);
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
    if opts.compaction != Compaction::Off {
        let shape = traffic::Shape {
            layout,
            regenerate,
            atomic: opts.compaction == Compaction::Atomic,
            slot_order: queue_order.is_slot(),
            sweep: uses_sweep,
            camera_in_place,
        };
        let mut items = traffic_items(&stats, settings, pool, shares.len());
        // The camera rays' bounce apart: in waves' queue histogram; regenerating, counted where
        // camera rays are made in place (their marks tell them apart).
        items.first_bounce = match &histogram {
            Some(h) => {
                let camera_hits = h.materials.iter().map(|m| m.first().copied().unwrap_or(0)).sum();
                Some((camera_hits, h.rays.get(1).copied().unwrap_or(0)))
            }
            None => (regenerate && camera_in_place).then_some(stats.first_bounce),
        };
        stats.state_traffic = Some(traffic::StateTraffic::model(&shape, &items));
    }
    let timings = timer.into_timings();
    if let Some(t) = &mut stats.state_traffic {
        t.add_times(&timings);
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
            timings,
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
            pool_size: Some(crate::options::PoolSize::Paths(pool)),
            queue_order,
            scan: if subgroup_scan { Scan::Subgroup } else { Scan::Workgroup },
            append: if subgroup_append { Append::Subgroup } else { Append::Lane },
            compute_passes: if shared_passes { ComputePasses::Shared } else { ComputePasses::PerDispatch },
            ..*opts
        },
    })
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
        rays: q[0] + q[1],
        hits: [q[2], q[3], q[4], q[5]],
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
