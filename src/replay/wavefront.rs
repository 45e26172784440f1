//! The wavefront replayed per pass (src/gpu/wavefront/). `--schedule waves`: per wave, generate
//! over the wave's paths, then per bounce intersect over the ray queue, one shade pass per
//! material kind the scene uses (or one over every hit), and with NEE the shadow pass. Each pass
//! runs one thread per queue entry, W consecutive entries per subgroup, the last subgroup of
//! every dispatch partial, and counts the slots `--instrument` counts.
//!
//! Queue order is arrival order (`--queue-order arrival`) or slot order (`slot`, `slot-depth`;
//! see [`Wave::regenerate`]). Arrival order is the one `--compaction-method scan` leaves, which
//! is stable over the producing pass's positions: intersect's positions in order → each
//! material queue; shade's positions (material queues laid end to end in kind order) → the next
//! ray queue and, in the same order, the shadow queue (appended atomically on the device, see
//! below). `--compaction-method atomic` leaves whatever order the atomics run in, which no
//! replay can know: it is modelled by the scan's order, which atomics aggregated per subgroup
//! approach when subgroups append in dispatch order. With
//! `--compaction off` every pass runs over the whole wave, one thread per path, and the lanes
//! whose path is not in that pass's queue idle. `--schedule regenerate`: see
//! [`Wave::regenerate`]: the schedule's checks every `--sync-every` iterations, the sample ring's
//! refill limit they move and the megakernel tail (`--tail megakernel`), by the rule the GPU's
//! decision pass runs (`schedule::Decision::after`).

use super::lockstep::{extrapolate, slot, traverse, Lane, SlotCounts};
use super::megakernel::bounce;
use super::paths::Paths;
use super::recorder::{is_hit, is_step, CLOSEST, SHADOW};
use super::ReplayJob;
use crate::camera::CameraFrame;
use crate::cpu::camera::Camera;
use crate::gpu::label;
use crate::gpu::wavefront::schedule::{shares, ChunkCounters, Decision, Progress, Ring};
use crate::gpu::wavefront::{Compaction, QueueOrder, ShadePasses, Tail, WavefrontOptions, DEFAULT_POOL};
use crate::layout::material_kind::COUNT as KINDS;
use crate::layout::DispatchParams;
use crate::options::{PoolSize, RunSchedule, Schedule};
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};

/// The label of the megakernel tail's pass (`src/gpu/wavefront/tail.rs`'s stage): its dispatches
/// are counted under it, its blocks in the `megakernel_*` slots (`work:megakernel`), as on the
/// device.
pub const TAIL_PASS: &str = crate::gpu::label::TAIL;

/// The shortest prefix the regenerating subset (`every` > 1) replays, in pools: long enough
/// that the job reaches its steady state between its start (a full pool at once) and its drain
/// (the last pool's paths ending), which the subset's two prefixes must share to cancel.
pub const MIN_SUBSET_POOLS: u64 = 8;

/// What the replay simulates of the wavefront's launch.
#[derive(Clone, Copy, Debug)]
pub struct Launch {
    /// Paths in flight (`--pool-size`; the device's default is 2^20, at most the samples).
    pub pool: u32,
    pub compaction: Compaction,
    pub shade: ShadePasses,
    /// `waves`, or `regenerate`: refills into the free slots every iteration.
    pub schedule: Schedule,
    /// The order of the queues (`auto` resolved as the device resolves it).
    pub queue_order: QueueOrder,
    /// Regenerating: iterations between the schedule's checks (`--sync-every`).
    pub sync_every: u32,
    /// Regenerating: whether the megakernel tail finishes the last paths (`--tail`).
    pub tail: Tail,
    /// The live fraction of the pool below which the tail takes over (`--tail-threshold`).
    pub tail_threshold: f64,
    /// Regenerating: pools in the sample ring (`--chunk-pools`).
    pub chunk_pools: u32,
    /// The sampled subset: 1 replays the whole frame; k > 1 about 1/k of it (see [`subset`]).
    pub every: u64,
}

impl Launch {
    /// The device's options this launch replays (for their checks).
    fn options(&self) -> WavefrontOptions {
        WavefrontOptions {
            pool_size: Some(PoolSize::Paths(self.pool)),
            compaction: self.compaction,
            shade: self.shade,
            schedule: self.schedule,
            queue_order: self.queue_order,
            sync_every: self.sync_every,
            tail: self.tail,
            tail_threshold: self.tail_threshold,
            chunk_pools: self.chunk_pools,
            ..WavefrontOptions::default()
        }
    }

    /// The shares (waves, or regenerating chunks) the device cuts `settings` into on `pool` slots.
    pub fn shares(&self, settings: &RenderSettings, pool: u32) -> Vec<DispatchParams> {
        shares(self.run_schedule(), settings.width * settings.height, settings.spp, pool, settings.max_depth)
    }

    pub fn run_schedule(&self) -> RunSchedule {
        if self.schedule == Schedule::Regenerate {
            RunSchedule::Regenerate
        } else {
            RunSchedule::Waves
        }
    }

    /// The launch `render` makes of `opts` (the whole frame), whose `--schedule auto` is
    /// resolved for the device replayed ([`WavefrontOptions::resolve`]).
    pub fn from_options(opts: &WavefrontOptions) -> Self {
        assert!(
            opts.schedule != Schedule::Auto,
            "the replay needs the schedule the device runs: resolve --schedule auto first"
        );
        Self {
            // `device` needs a device: the CLI refuses it, and a library caller gets the default.
            pool: match opts.pool_size {
                Some(PoolSize::Paths(n)) => n,
                None | Some(PoolSize::Device) => DEFAULT_POOL,
            },
            compaction: opts.compaction,
            shade: opts.shade,
            schedule: opts.schedule,
            queue_order: opts.queue_order,
            sync_every: opts.sync_every,
            tail: opts.tail,
            tail_threshold: opts.tail_threshold,
            chunk_pools: opts.chunk_pools,
            every: 1,
        }
    }
}

/// The replay at each width: slot counts; per pass, dispatches recorded and how many were
/// empty (zero workgroups: nothing queued).
pub struct Replayed {
    pub counts: Vec<(u32, SlotCounts)>,
    pub dispatches: BTreeMap<String, Dispatches>,
    /// Shares (waves, or regenerating shares) of the frame, and of them replayed.
    pub waves: usize,
    pub waves_replayed: usize,
    /// Samples replayed (all of the frame's without a subset).
    pub samples_replayed: u64,
    /// The queue order replayed (`auto` resolved).
    pub queue_order: QueueOrder,
    /// What the schedule did, as `ScheduleStats` counts it: iterations recorded, and the
    /// megakernel tail's passes and the paths they finished.
    pub iterations: u64,
    pub tail_passes: u64,
    pub tail_paths: u64,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Dispatches {
    pub recorded: u64,
    pub empty: u64,
}

/// The host's side of a regenerating share (src/gpu/wavefront/mod.rs): when it checks the
/// counters, what it does then.
#[derive(Clone, Copy, Debug)]
struct Host {
    sync_every: u32,
    tail: bool,
    threshold: f64,
}

/// One share's replay at one width: slot counts, dispatches per pass, what its schedule did.
type ShareReplay = (SlotCounts, BTreeMap<String, Dispatches>, ShareStats);

/// What one regenerating share's host loop did.
#[derive(Default)]
struct ShareStats {
    iterations: u64,
    tail_passes: u64,
    tail_paths: u64,
}

/// The sampled subset of `plan` for `every` = k (1: all of it), as (index in the plan) of the
/// shares replayed. Waves: whole waves, one in k, the offset turning by one at each pass over
/// the image (the waves holding the same sample numbers), so that when a pass holds several
/// waves (a pool smaller than the image) every region of the image is drawn alike rather than
/// the same rows at every pass.
pub fn subset(plan: &[DispatchParams], every: u64) -> Vec<usize> {
    let k = every.max(1);
    let (mut pass, mut within, mut start) = (0u64, 0u64, None);
    let mut out = Vec::new();
    for (i, d) in plan.iter().enumerate() {
        if start.is_some_and(|s| s != d.sample_start) {
            pass += 1;
            within = 0;
        }
        start = Some(d.sample_start);
        if (within + pass).is_multiple_of(k) {
            out.push(i);
        }
        within += 1;
    }
    out
}

/// The regenerating methods' subset for `every` = k (1: the whole frame): the frame at
/// ⌈spp / k⌉ samples per pixel (the same paths, sample for sample: the first samples of every
/// pixel, so the image's regions keep their weight), the shorter of the two prefixes
/// [`replay`] replays, each as a job of its own with the full job's pool and queue order; the
/// other holds twice its samples. A prefix alone would weigh the job's start (a full pool at
/// once) and drain (the last pool's paths ending) k times as much as the frame does; the
/// difference of the two cancels them, and the frame's counts are the shorter's plus that
/// difference scaled to the rest of the frame ([`SlotCounts::extrapolate`]). The frame itself
/// where the two prefixes would hold all of it (2⌈spp / k⌉ ≥ spp); refused where k exceeds the
/// spp, or where the shorter prefix holds fewer than [`MIN_SUBSET_POOLS`] pools
/// (`pool`: for the regenerating megakernel, its persistent threads). `what`: the option's name
/// in errors.
pub fn regenerating_subset(
    settings: &RenderSettings,
    every: u64,
    pool: u64,
    what: &str,
) -> Result<RenderSettings> {
    if every <= 1 {
        return Ok(settings.clone());
    }
    if every > settings.spp as u64 {
        bail!(
            "{what} {every}: a regenerating method's subset is the first spp/{every} samples of every pixel, and the \
             frame has {} per pixel; give {what} of at most {}",
            settings.spp,
            settings.spp
        );
    }
    let spp = (settings.spp as u64).div_ceil(every) as u32;
    if 2 * spp as u64 >= settings.spp as u64 {
        // The two prefixes would hold the whole frame: it is replayed whole.
        return Ok(settings.clone());
    }
    let sub = RenderSettings { spp, ..settings.clone() };
    if sub.sample_count() < MIN_SUBSET_POOLS * pool {
        bail!(
            "{what} {every}: the subset ({spp} samples per pixel, {} samples) would hold fewer than {MIN_SUBSET_POOLS} \
             pools (or persistent thread sets) of {pool}: too short for the steady state; give a smaller {what}",
            sub.sample_count()
        );
    }
    Ok(sub)
}

/// Replays the wavefront at every width in `widths`.
pub fn replay(job: ReplayJob, launch: Launch) -> Result<Replayed> {
    let ReplayJob { scene, frame, settings, widths } = job;
    if launch.pool == 0 {
        bail!("replay of the wavefront: the pool must hold at least 1 path");
    }
    if launch.every == 0 {
        bail!("--every must be at least 1 (1: the whole frame)");
    }
    if launch.shade == ShadePasses::PerTexture {
        bail!(
            "replay of the wavefront: --shade per-texture is not modelled (the replay's lockstep \
             follows material kinds, not texture code paths); replay per-material or single"
        );
    }
    let regenerate = launch.schedule == Schedule::Regenerate;
    if regenerate && launch.compaction == Compaction::Off {
        bail!(
            "replay of the regenerating wavefront: --compaction off runs passes over the pool by slot, which \
             follows the free list's atomic order; replay it with --compaction on"
        );
    }
    crate::options::check_wavefront(&launch.options())?;
    // The full job's pool and queue order, whatever the subset.
    let pool = launch.pool.min(u32::try_from(settings.sample_count()).unwrap_or(u32::MAX));
    let order = launch.queue_order.resolve(launch.schedule, launch.compaction, settings.sample_count(), pool);
    let job = Job { pool, order };
    if !regenerate {
        let plan = launch.shares(settings, pool);
        return replay_shares(scene, frame, settings, widths, launch, job, &subset(&plan, launch.every));
    }
    let short = regenerating_subset(settings, launch.every, pool as u64, "--every")?;
    let all = |s: &RenderSettings| {
        let plan = launch.shares(s, pool);
        (0..plan.len()).collect::<Vec<_>>()
    };
    if short.spp == settings.spp {
        return replay_shares(scene, frame, settings, widths, launch, job, &all(settings));
    }
    let long = RenderSettings { spp: 2 * short.spp, ..settings.clone() };
    let a = replay_shares(scene, frame, &short, widths, launch, job, &all(&short))?;
    let b = replay_shares(scene, frame, &long, widths, launch, job, &all(&long))?;
    let f = (settings.sample_count() - short.sample_count()) as f64
        / (long.sample_count() - short.sample_count()) as f64;
    let mut r = a.extrapolate(b, f);
    r.waves = all(settings).len();
    Ok(r)
}

/// The full job's pool and resolved queue order, which a subset keeps.
#[derive(Clone, Copy, Debug)]
pub struct Job {
    pub pool: u32,
    pub order: QueueOrder,
}

impl Replayed {
    /// The frame's figures from two nested prefixes (`self` the shorter, `long` the other) by
    /// [`SlotCounts::extrapolate`]; the dispatches, iterations and tail counts alike.
    fn extrapolate(self, long: Replayed, f: f64) -> Replayed {
        let x = |a: u64, b: u64| extrapolate(a, b, f);
        let mut dispatches = BTreeMap::new();
        for (pass, b) in &long.dispatches {
            let a = self.dispatches.get(pass).copied().unwrap_or_default();
            dispatches.insert(
                pass.clone(),
                Dispatches { recorded: x(a.recorded, b.recorded), empty: x(a.empty, b.empty) },
            );
        }
        Replayed {
            counts: self
                .counts
                .iter()
                .zip(&long.counts)
                .map(|((w, a), (_, b))| (*w, SlotCounts::extrapolate(a, b, f)))
                .collect(),
            dispatches,
            waves: long.waves,
            waves_replayed: self.waves_replayed + long.waves_replayed,
            samples_replayed: self.samples_replayed + long.samples_replayed,
            queue_order: self.queue_order,
            iterations: x(self.iterations, long.iterations),
            tail_passes: x(self.tail_passes, long.tail_passes),
            tail_paths: x(self.tail_paths, long.tail_paths),
        }
    }
}

/// Replays the shares `chosen` (indices into `shares(…)` of `settings`) of the wavefront with
/// the pool and queue order of `job`, at every width in `widths`: [`replay`]'s work, and the
/// way to replay a subset of one's own (the tests' deliberately biased one).
pub fn replay_shares(
    scene: &PackedScene,
    frame: &CameraFrame,
    settings: &RenderSettings,
    widths: &[u32],
    launch: Launch,
    job: Job,
    chosen: &[usize],
) -> Result<Replayed> {
    let Job { pool, order } = job;
    let regenerate = launch.schedule == Schedule::Regenerate;
    let camera = Camera::<f32>::new(frame);
    let plan = launch.shares(settings, pool);
    // As the host: every share's ring has the largest share's chunks (one pool) and at most
    // `chunk_pools` of them (the adapter's binding limit, which can only shrink the ring, is not
    // known here).
    let share = |d: &DispatchParams| d.pixel_count * d.sample_count;
    let largest = plan.iter().map(share).max().unwrap_or(1);
    let budget = (launch.chunk_pools as u64 * pool as u64).clamp(pool as u64, u32::MAX as u64);
    let ring = Ring::new(largest, pool, budget);
    let host = Host {
        sync_every: launch.sync_every,
        tail: launch.tail == Tail::Megakernel,
        threshold: launch.tail_threshold,
    };
    let kinds = scene.material_kinds_used();
    let shadow_pass = settings.nee && !scene.lights.is_empty();
    let mut counts: Vec<SlotCounts> = widths.iter().map(|_| SlotCounts::new()).collect();
    let mut dispatches = BTreeMap::new();
    let mut stats = ShareStats::default();
    let mut samples_replayed = 0;
    for &i in chosen {
        let d = &plan[i];
        let n = share(d) as u64;
        samples_replayed += n;
        let paths = Paths::record(scene, &camera, settings, d, 0..n);
        let per_width: Vec<Result<ShareReplay>> = widths
            .par_iter()
            .map(|&w| {
                let lanes = paths.lanes();
                let n = lanes.len();
                let mut wave = Wave {
                    lanes,
                    width: w,
                    counts: SlotCounts::new(),
                    dispatches: BTreeMap::new(),
                    compaction: launch.compaction != Compaction::Off,
                    // In waves, slot l traces sample l.
                    slot_of: if order.is_slot() { (0..n).collect() } else { Vec::new() },
                    first_bounce: vec![false; if order == QueueOrder::SlotDepth { n } else { 0 }],
                    flushed: Vec::new(),
                };
                let mut s = ShareStats::default();
                if regenerate {
                    let r = Ring { paths: n as u32, ..ring };
                    s = wave.regenerate(
                        pool as usize,
                        r,
                        host,
                        settings.max_depth,
                        &kinds,
                        launch.shade,
                        shadow_pass,
                    )?;
                } else {
                    wave.waves(settings.max_depth, &kinds, launch.shade, shadow_pass);
                    s.iterations = settings.max_depth as u64;
                }
                Ok((wave.counts, wave.dispatches, s))
            })
            .collect();
        let per_width = per_width.into_iter().collect::<Result<Vec<_>>>()?;
        for (a, (b, _, _)) in counts.iter_mut().zip(&per_width) {
            a.add(b);
        }
        for (pass, n) in &per_width[0].1 {
            let e: &mut Dispatches = dispatches.entry(pass.clone()).or_default();
            e.recorded += n.recorded;
            e.empty += n.empty;
        }
        let s = &per_width[0].2;
        stats.iterations += s.iterations;
        stats.tail_passes += s.tail_passes;
        stats.tail_paths += s.tail_paths;
    }
    Ok(Replayed {
        counts: widths.iter().copied().zip(counts).collect(),
        dispatches,
        waves: plan.len(),
        waves_replayed: chosen.len(),
        samples_replayed,
        queue_order: order,
        iterations: stats.iterations,
        tail_passes: stats.tail_passes,
        tail_paths: stats.tail_paths,
    })
}

/// One wave's paths at one width.
struct Wave<'a> {
    lanes: Vec<Lane<'a>>,
    width: u32,
    counts: SlotCounts,
    dispatches: BTreeMap<String, Dispatches>,
    /// Whether passes run over queues (scan or atomic) rather than the whole wave.
    compaction: bool,
    /// Slot order: each lane's slot in the pool (empty in arrival order).
    slot_of: Vec<usize>,
    /// Keyed by depth: whether the lane's path was started by the last refill (its next ray is
    /// its first bounce); empty without the key.
    first_bounce: Vec<bool>,
    /// Regenerating with the tail: whether the lane's path was finished by a tail pass while
    /// still on the ray queue (the next intersect frees its slot: an idle entry there); empty
    /// until a tail runs.
    flushed: Vec<bool>,
}

impl Wave<'_> {
    /// `--schedule waves`: every path starts together; `max_depth` iterations.
    fn waves(&mut self, max_depth: u32, kinds: &[u32], shade: ShadePasses, shadow_pass: bool) {
        let all: Vec<usize> = (0..self.lanes.len()).collect();
        let threads: Vec<Option<usize>> = all.iter().map(|&l| Some(l)).collect();
        self.pass(label::GENERATE, &threads, |_, _| {});
        let mut rays = all;
        for _ in 0..max_depth {
            rays = self.iteration(&rays, kinds, shade, shadow_pass);
        }
    }

    /// `--schedule regenerate`, as the host runs a share (src/gpu/wavefront/mod.rs): batches of
    /// `sync_every` iterations (with the tail, one iteration once every sample has started),
    /// each followed by a check of the counters at which the host adds the complete chunks to
    /// the film, runs the megakernel tail where it is due and moves the refill limit to the
    /// sample ring's new end (`Ring`, `ChunkCounters`: the host's own functions).
    ///
    /// An iteration: while the host's last check found samples not yet started, the refill
    /// starts the next samples in the slots free (the pool less the paths still queued, up to
    /// the refill limit), appended at the ray queue's end in sample order; then one bounce of
    /// every queued path. In arrival order which slot a refill takes (the free list is a stack)
    /// does not move a lane in a compacted queue. In slot order it does: the refill takes the
    /// lowest free slots in ascending order (the scan's free list), and the next ray queue and
    /// the shadow queue list their paths by slot; keyed by depth, the last refill's paths (about
    /// to trace their first bounce) after the others.
    #[allow(clippy::too_many_arguments)]
    fn regenerate(
        &mut self,
        pool: usize,
        r: Ring,
        host: Host,
        max_depth: u32,
        kinds: &[u32],
        shade: ShadePasses,
        shadow_pass: bool,
    ) -> Result<ShareStats> {
        let n = self.lanes.len();
        let paths = r.paths;
        let slot_order = !self.slot_of.is_empty();
        let mut free: BTreeSet<usize> = if slot_order { (0..pool).collect() } else { Default::default() };
        let (mut next, mut rays) = (0usize, Vec::new());
        // Which lanes are still queued after an iteration (reset after each use).
        let mut live = vec![false; n];
        // Finished samples per chunk (the ring's counters, by chunk rather than modulo the ring).
        let mut finished = vec![0u32; r.chunks() as usize];
        let chunk = r.chunk as usize;
        let mut stats = ShareStats::default();
        let mut fill_limit = r.fill_limit(0) as usize;
        let mut progress = Progress::new(paths, max_depth, host.sync_every);
        let mut refill = true;
        let (mut oldest, mut started_before) = (0u32, 0u32);
        let one_refill = paths <= (pool as u32).min(r.fill_limit(0));
        loop {
            for _ in 0..host.sync_every {
                // The refill (recorded while the last check found samples to start).
                let fresh: Vec<usize> = if refill {
                    (next..n.min(fill_limit).min(next + pool - rays.len()).max(next)).collect()
                } else {
                    Vec::new()
                };
                next += fresh.len();
                self.refill(refill, &fresh, &rays, &mut free);
                rays.extend(fresh);
                let before = std::mem::take(&mut rays);
                rays = self.iteration(&before, kinds, shade, shadow_pass);
                stats.iterations += 1;
                // The paths that ended (those the tail finished were counted then); their slots
                // are free for the next refill, the flushed ones' too (intersect freed them).
                rays.iter().for_each(|&l| live[l] = true);
                for &l in &before {
                    if !live[l] && !self.flushed.get(l).is_some_and(|&f| f) {
                        finished[l / chunk] += 1;
                    }
                }
                if slot_order {
                    free.extend(before.iter().filter(|&&l| !live[l]).map(|&l| self.slot_of[l]));
                }
                rays.iter().for_each(|&l| live[l] = false);
                before.iter().for_each(|&l| {
                    if let Some(f) = self.flushed.get_mut(l) {
                        *f = false;
                    }
                });
                if host.tail && (one_refill || !refill) {
                    break;
                }
            }
            // The check: the counters as ChunkCounters::parse gives them.
            let mut ring = vec![0u32; r.ring as usize];
            for c in oldest..r.chunks().min(oldest + r.ring) {
                ring[(c % r.ring) as usize] = finished[c as usize];
            }
            let started = next as u32;
            let c = ChunkCounters { started, finished: oldest * r.chunk + ring.iter().sum::<u32>(), ring };
            progress.check(c.finished, stats.iterations as u32)?;
            // The wavefront's own rule (gpu/wavefront/schedule.rs), not a copy of it.
            let threshold = host.tail.then_some(host.threshold);
            let decision = Decision::after(&r, &c, oldest, started_before, pool as u32, threshold);
            refill = decision.refill;
            if let Some(bound) = decision.tail_bound {
                let done = self.tail(&rays, r.end(bound - 1) as usize);
                for &l in &done {
                    finished[l / chunk] += 1;
                }
                stats.tail_passes += 1;
                stats.tail_paths += done.len() as u64;
            }
            let added = decision.added;
            started_before = c.started;
            if added > oldest {
                oldest = added;
                fill_limit = r.fill_limit(oldest) as usize;
            }
            if oldest == r.chunks() {
                return Ok(stats);
            }
            if c.finished == paths {
                bail!("replay of the regenerating wavefront: every sample finished but {oldest} of {} chunks added", r.chunks());
            }
        }
    }

    /// The refill's pass (recorded while the last check found samples to start): `fresh` lanes
    /// start their first bounce beside the queued `rays`; in slot order each takes the lowest
    /// free slot.
    fn refill(&mut self, recorded: bool, fresh: &[usize], rays: &[usize], free: &mut BTreeSet<usize>) {
        if !self.first_bounce.is_empty() {
            rays.iter().for_each(|&l| self.first_bounce[l] = false);
            fresh.iter().for_each(|&l| self.first_bounce[l] = true);
        }
        if !self.slot_of.is_empty() {
            for &l in fresh {
                self.slot_of[l] = free.pop_first().expect("a free slot for every refill");
            }
        }
        if recorded {
            let threads: Vec<Option<usize>> = fresh.iter().map(|&l| Some(l)).collect();
            self.pass(label::GENERATE, &threads, |_, _| {});
        }
    }

    /// The megakernel tail (shaders/wavefront/tail.wgsl): one thread per entry of the ray queue
    /// the last shade pass filled, W per subgroup; the lanes whose sample is below `bound` run
    /// their path to its end in the megakernel's bounce loop, in lockstep (as the naive
    /// megakernel's replay), the others return at once. Returns the lanes it finished, which
    /// stay on the ray queue, flushed, until the next intersect frees their slots.
    fn tail(&mut self, queue: &[usize], bound: usize) -> Vec<usize> {
        let d = self.dispatches.entry(TAIL_PASS.to_string()).or_default();
        d.recorded += 1;
        d.empty += queue.is_empty() as u64;
        if self.flushed.is_empty() {
            self.flushed = vec![false; self.lanes.len()];
        }
        let mut done = Vec::new();
        for group in queue.chunks(self.width as usize) {
            let mut alive: Vec<usize> =
                group.iter().copied().filter(|&l| l < bound && !self.flushed[l]).collect();
            done.extend(&alive);
            while !alive.is_empty() {
                alive = bounce(&mut self.lanes, &alive, self.width, &mut self.counts);
            }
        }
        done.iter().for_each(|&l| self.flushed[l] = true);
        done
    }

    /// In slot order, `queue` as the scan over the pool lists it: by slot; keyed by depth
    /// (`first_key`), the paths on their first bounce after the others.
    fn slot_sort(&self, queue: &mut [usize], first_key: bool) {
        if self.slot_of.is_empty() {
            return;
        }
        let key = |l: usize| (first_key && self.first_bounce.get(l) == Some(&true), self.slot_of[l]);
        queue.sort_by_key(|&l| key(l));
    }

    /// One iteration over the ray queue `rays`: intersect, shade pass by pass, shadow; returns
    /// the next ray queue.
    fn iteration(
        &mut self,
        rays: &[usize],
        kinds: &[u32],
        shade: ShadePasses,
        shadow_pass: bool,
    ) -> Vec<usize> {
        // Intersect: closest hits; hits go to their material's queue in queue order.
        let mut material: [Vec<usize>; KINDS] = Default::default();
        let queue = self.queue(rays);
        self.pass(label::INTERSECT, &queue, |wave, active| {
            active.iter().for_each(|&l| wave.lanes[l].at += 1);
            traverse(&mut wave.lanes, active, slot("intersect_traverse_inner"), wave.width, &mut wave.counts);
        });
        for &l in rays {
            if let Some(e) = self.lanes[l].next().filter(|&e| is_hit(e)) {
                let by_kind = matches!(shade, ShadePasses::PerMaterial | ShadePasses::Sorted);
                let k = if by_kind { ((e & 0xff) as usize).min(KINDS - 1) } else { 0 };
                material[k].push(l);
            }
        }
        // Shade, pass by pass in kind order: the next ray queue and the shadow queue.
        let (mut next, mut shadow) = (Vec::new(), Vec::new());
        let passes: Vec<(usize, &str)> = match shade {
            ShadePasses::PerMaterial => kinds
                .iter()
                .map(|&k| (k as usize, label::SHADE_BY_KIND[(k as usize).min(KINDS - 1)]))
                .collect(),
            ShadePasses::Single => vec![(0, label::SHADE)],
            // One pass over the kinds' queues end to end, in kind order (queue_setup_shade's
            // positions): subgroups of one kind but at the seams. Its lanes are counted in the
            // single shade pass's slot, as the device counts them (shade.wgsl's PASS_SHADE).
            ShadePasses::Sorted => {
                let sorted: Vec<usize> = material.iter().flatten().copied().collect();
                material[0] = sorted;
                vec![(0, label::SHADE)]
            }
            ShadePasses::PerTexture => unreachable!("the replay refuses --shade per-texture"),
        };
        for (k, name) in passes {
            let queue = self.queue(&material[k]);
            // A path the roulette ends right after its shadow ray leaves every queue in shade,
            // which traces that shadow ray itself (shade.wgsl): in the shade pass's lockstep,
            // its steps counted as the shadow pass's traversal, and not on the shadow queue.
            let ends_in_shade: std::collections::HashSet<usize> =
                material[k].iter().copied().filter(|&l| ends_after_its_shadow_ray(&self.lanes[l])).collect();
            self.pass(name, &queue, |wave, active| {
                let ended: Vec<usize> =
                    active.iter().copied().filter(|l| ends_in_shade.contains(l)).collect();
                ended.iter().for_each(|&l| wave.lanes[l].at += 2); // the hit, then the shadow ray
                traverse(
                    &mut wave.lanes,
                    &ended,
                    slot("shadow_traverse_inner"),
                    wave.width,
                    &mut wave.counts,
                );
            });
            for &l in &material[k] {
                if ends_in_shade.contains(&l) {
                    continue;
                }
                let lane = &mut self.lanes[l];
                lane.at += 1;
                if lane.next() == Some(SHADOW) {
                    shadow.push(l);
                }
                if after_shadow(lane) == Some(CLOSEST) {
                    next.push(l);
                }
            }
        }
        self.slot_sort(&mut shadow, false);
        self.slot_sort(&mut next, true);
        if shadow_pass {
            let queue = self.queue(&shadow);
            self.pass(label::SHADOW, &queue, |wave, active| {
                active.iter().for_each(|&l| wave.lanes[l].at += 1);
                traverse(
                    &mut wave.lanes,
                    active,
                    slot("shadow_traverse_inner"),
                    wave.width,
                    &mut wave.counts,
                );
            });
        }
        next
    }

    /// A pass's threads: the queue's entries in order, or without compaction the whole wave
    /// with the paths not in `queued` idle (None).
    /// A path the tail flushed is an idle entry (intersect frees its slot and returns).
    fn queue(&self, queued: &[usize]) -> Vec<Option<usize>> {
        if self.compaction {
            return queued.iter().map(|&l| (!self.flushed.get(l).is_some_and(|&f| f)).then_some(l)).collect();
        }
        let mut threads = vec![None; self.lanes.len()];
        queued.iter().for_each(|&l| threads[l] = Some(l));
        threads
    }

    /// One dispatch of pass `name` over `threads`, W per subgroup: the entry slot counted with
    /// each subgroup's active lanes, then `body` run on them in lockstep.
    fn pass(&mut self, name: &str, threads: &[Option<usize>], mut body: impl FnMut(&mut Self, &[usize])) {
        let d = self.dispatches.entry(name.to_string()).or_default();
        d.recorded += 1;
        d.empty += threads.is_empty() as u64;
        for group in threads.chunks(self.width as usize) {
            let active: Vec<usize> = group.iter().flatten().copied().collect();
            self.counts.count(slot(name), active.len(), self.width);
            if !active.is_empty() {
                body(self, &active);
            }
        }
    }
}

/// Whether the lane, at a hit, traces a shadow ray there and then nothing more: only Russian
/// roulette ends a path after a shadow ray (NEE samples a light only where the path may go on).
fn ends_after_its_shadow_ray(lane: &Lane) -> bool {
    let after_hit = Lane { events: lane.events, at: lane.at + 1 };
    after_hit.next() == Some(SHADOW) && after_shadow(&after_hit).is_none()
}

/// The lane's next event past a pending shadow ray's traversal (what follows the bounce).
fn after_shadow(lane: &Lane) -> Option<u32> {
    let mut i = lane.at;
    if lane.events.get(i) == Some(&SHADOW) {
        i += 1;
        while lane.events.get(i).is_some_and(|&e| is_step(e)) {
            i += 1;
        }
    }
    lane.events.get(i).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One wave in k, the offset turning per pass: over k passes every wave position (image
    /// region) is drawn once, where a fixed offset would draw positions 0, k, 2k, … every time.
    #[test]
    fn the_wave_subset_turns_over_the_image() {
        // 24 pixels, 4 spp, waves of 4 pixels: 6 waves per pass, 24 in all.
        let plan = shares(RunSchedule::Waves, 24, 4, 4, 8);
        assert_eq!(plan.len(), 24);
        let drawn = subset(&plan, 3);
        assert_eq!(drawn.len(), 8);
        let mut per_region = [0; 6];
        for &i in &drawn {
            per_region[(plan[i].pixel_offset / 4) as usize] += 1;
        }
        // 4 passes of 6 waves, one in 3: passes 0..3 draw regions {0,3}, {2,5}, {1,4}, {0,3}.
        assert_eq!(per_region, [2, 1, 1, 2, 1, 1]);
        assert_eq!(subset(&plan, 1).len(), 24);
        // One wave per pass (the pool holds the image): every k-th pass.
        let whole = shares(RunSchedule::Waves, 24, 6, 24, 8);
        assert_eq!(subset(&whole, 2), vec![0, 2, 4]);
    }
}
