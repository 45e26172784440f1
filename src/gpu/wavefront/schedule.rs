//! How the wavefront schedules its pool (`--schedule`), and what the schedule cost: dispatches
//! (empty ones apart), iterations (idle ones apart) and the intersect passes' occupancy, read
//! from the scheduling counters of `shaders/wavefront/shared/path_state.wgsl`.

use super::super::buffers::{read_back, Staging};
use super::super::context::GpuContext;
use super::super::dispatch_plan;
use super::path_state::{
    schedule_word as word, PathState, COUNTER_RING, COUNTER_SCHEDULE, COUNTER_STATS, QUEUE_COUNT,
};
use crate::layout::DispatchParams;
use anyhow::{bail, Result};

pub use crate::options::{
    RunSchedule, Schedule, CHUNK_POOLS, DEFAULT_SYNC_EVERY, MAX_CHUNK_POOLS, MAX_SYNC_EVERY,
};

/// Most samples in one share when regenerating: the share's sample index is a u32, and the
/// shaders add a pixel count to it.
pub const MAX_SHARE: u64 = 1 << 31;

/// Most samples in one share (a wave, or a regenerating share) such that none of the share's
/// 32-bit counters can wrap: a sample adds at most `max_depth` entries to the intersect count,
/// to the bounce histogram's rows (one row holds every bounce when regenerating) and to the
/// shadow queue's, and the host reads and zeroes them after every share (`add_share`,
/// `add_wave_histogram`). The one slack entry covers the camera ray.
pub fn counter_safe_share(max_depth: u32) -> u64 {
    u32::MAX as u64 / (max_depth as u64 + 1)
}

/// The render's shares: waves of at most `pool` samples, or regenerating shares as large as a
/// share's sample index allows; either within [`counter_safe_share`].
pub fn shares(
    schedule: RunSchedule,
    pixels: u32,
    spp: u32,
    pool: u32,
    max_depth: u32,
) -> Vec<DispatchParams> {
    let safe = counter_safe_share(max_depth);
    match schedule {
        RunSchedule::Waves => dispatch_plan::plan(pixels, spp, (pool as u64).min(safe), pool),
        RunSchedule::Regenerate => dispatch_plan::plan(pixels, spp, MAX_SHARE.min(safe), u32::MAX),
    }
}

/// Samples the sample ring may hold: `chunk_pools` pools, within one storage binding of
/// 16-byte samples.
pub fn ring_budget(ctx: &GpuContext, pool: u32, chunk_pools: u32) -> u64 {
    let limit = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size) / 16;
    (chunk_pools as u64 * pool as u64).min(limit).clamp(pool as u64, u32::MAX as u64)
}

/// The sample ring of a regenerating share: its samples are cut into chunks of `chunk` (one
/// pool), the last one shorter; finished samples wait in a ring of `ring` chunks until the
/// oldest chunks are complete and added to the film, and refills never run more than `ring`
/// chunks ahead of the oldest one not yet added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ring {
    pub paths: u32,
    pub chunk: u32,
    pub ring: u32,
}

impl Ring {
    /// The ring for a share of `paths` samples, a pool of `pool` and `budget` samples of ring.
    pub fn new(paths: u32, pool: u32, budget: u64) -> Self {
        let chunk = pool.min(paths).max(1);
        let chunks = paths.div_ceil(chunk).max(1);
        let ring = (budget / chunk as u64).clamp(1, chunks as u64) as u32;
        Self { paths, chunk, ring }
    }

    pub fn chunks(&self) -> u32 {
        self.paths.div_ceil(self.chunk).max(1)
    }

    /// Samples in chunk `c` (the last may be short).
    pub fn len(&self, c: u32) -> u32 {
        self.end(c) - c * self.chunk
    }

    /// One past chunk `c`'s last sample.
    pub fn end(&self, c: u32) -> u32 {
        ((c as u64 + 1) * self.chunk as u64).min(self.paths as u64) as u32
    }

    /// Samples the ring holds.
    pub fn samples(&self) -> u32 {
        self.chunk * self.ring
    }

    /// The fill limit once the chunks before `oldest` are added: refills start no sample of a
    /// chunk `ring` or more after it.
    pub fn fill_limit(&self, oldest: u32) -> u32 {
        if oldest + self.ring >= self.chunks() {
            return self.paths;
        }
        (oldest + self.ring) * self.chunk
    }

    /// The chunks from `oldest` on that are complete, in order (the first incomplete one ends
    /// the run): `finished[c % ring]` counts chunk c's finished samples, for the `ring` chunks
    /// from `oldest` on (the ones refills may have started).
    pub fn complete_from(&self, oldest: u32, finished: &[u32]) -> u32 {
        let mut c = oldest;
        let window = self.chunks().min(oldest.saturating_add(self.ring));
        while c < window && finished[(c % self.ring) as usize] == self.len(c) {
            c += 1;
        }
        c
    }

    /// With the megakernel tail: the chunks before the returned one should be finished by it now
    /// (from `complete`, the first incomplete chunk), so that the refills of the next batch,
    /// expected to start `expected` samples, do not stop at the ring's end. Only chunks whose
    /// samples have all started and that have at most `max_live` paths left are taken, oldest
    /// first.
    pub fn flush_to(
        &self,
        complete: u32,
        started: u32,
        expected: u32,
        finished: &[u32],
        max_live: f64,
    ) -> u32 {
        let mut c = complete;
        while c < self.chunks()
            && self.fill_limit(c) < self.paths
            && self.fill_limit(c).saturating_sub(started) < expected
            && self.end(c) <= started
            && (self.len(c) - finished[(c % self.ring) as usize]) as f64 <= max_live
        {
            c += 1;
        }
        c
    }
}

/// A regenerating share's progress, read back between batches of iterations.
pub struct ChunkCounters {
    /// Samples started (handed to a slot).
    pub started: u32,
    /// Samples whose path has ended: those of the chunks already in the film and the ring's.
    pub finished: u32,
    /// Finished samples of each chunk of the ring, by chunk index modulo the ring.
    pub ring: Vec<u32>,
}

impl ChunkCounters {
    /// Bytes of the counter buffer a check reads (the schedule words and the ring's counts).
    pub fn bytes(r: &Ring) -> u64 {
        (COUNTER_RING + r.ring as u64) * 4
    }

    /// Records the copy of the counters a check reads into `staging`, at the end of the batch
    /// the check follows (so the check adds no submission of its own).
    pub fn copy(enc: &mut wgpu::CommandEncoder, staging: &Staging, state: &PathState, r: &Ring) {
        staging.copy(enc, &state.counters, Self::bytes(r));
    }

    /// The counters of `r` as [`Self::copy`] copied them (`words`, from the buffer's start), with
    /// what the GPU's decision pass adds: the iterations so far and whether the share is done.
    pub fn parse(words: &[u32], r: &Ring) -> (Self, Readback) {
        let w = |i: usize| words[COUNTER_SCHEDULE as usize + i];
        let ring = words[COUNTER_RING as usize..(COUNTER_RING + r.ring as u64) as usize].to_vec();
        // Chunks in the film have their counts taken off the ring (queue_setup.wgsl's
        // schedule_decide), so the ring holds only the others' finished samples.
        let in_ring = ring.iter().fold(0u32, |a, &n| a.wrapping_add(n));
        let started = w(word::NEXT_SAMPLE);
        let finished = w(word::OLDEST).wrapping_mul(r.chunk).wrapping_add(in_ring);
        let back = Readback {
            iteration: w(word::ITERATION),
            done: w(word::DONE) != 0,
            failed: w(word::FAILED) != 0,
            oldest: w(word::OLDEST),
        };
        (Self { started, finished, ring }, back)
    }

    /// Paths in flight.
    pub fn live(&self) -> u32 {
        self.started - self.finished
    }

    /// Whether the megakernel tail should finish the share of `paths` samples now: every sample
    /// started, and at most `threshold` × `pool` paths still going.
    pub fn tail_due(&self, paths: u32, threshold: f64, pool: u32) -> bool {
        self.started == paths && (self.live() as f64) <= threshold * pool as f64
    }
}

/// What a read-back of a regenerating share's counters says beyond [`ChunkCounters`]: the GPU's
/// decision pass keeps the schedule's state (queue_setup.wgsl's `schedule_decide`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Readback {
    /// Iterations the GPU has run (those after the share's end apart).
    pub iteration: u32,
    /// Whether every chunk is in the film: the host stops recording iterations.
    pub done: bool,
    /// Whether every sample finished with chunks left out of the film (a bug).
    pub failed: bool,
    /// The first chunk not yet in the film.
    pub oldest: u32,
}

/// What is decided after a check of a regenerating share: the one rule the wavefront's decision
/// pass (`schedule_decide` in shaders/wavefront/queue_setup.wgsl, its twin in
/// shaders/wavefront/shared/schedule_rule.wgsl, checked against this one by tests/suite/schedule_rule.rs)
/// and its lockstep replay (`replay/wavefront.rs`) both follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decision {
    /// Whether the next iterations refill: samples are left to start.
    pub refill: bool,
    /// The first chunk from the oldest on that is not complete.
    pub complete: u32,
    /// With the tail: run it now over the chunks below this bound (above `complete`): every
    /// chunk once the share's end is due, else the oldest ones the ring needs back.
    pub tail_bound: Option<u32>,
    /// The chunks `[oldest, added)` go into the film now.
    pub added: u32,
}

impl Decision {
    /// The decision after the check `c` of the share in ring `r`: `oldest` is the first chunk not
    /// yet in the film, `started_before` the samples started at the previous check, and
    /// `tail_threshold` the tail's threshold where the render has a tail.
    pub fn after(
        r: &Ring,
        c: &ChunkCounters,
        oldest: u32,
        started_before: u32,
        pool: u32,
        tail_threshold: Option<f64>,
    ) -> Self {
        let complete = r.complete_from(oldest, &c.ring);
        let tail_bound = tail_threshold.and_then(|t| {
            let bound = if c.tail_due(r.paths, t, pool) {
                r.chunks()
            } else {
                r.flush_to(complete, c.started, c.started - started_before, &c.ring, t * pool as f64)
            };
            (bound > complete).then_some(bound)
        });
        Self { refill: c.started < r.paths, complete, tail_bound, added: tail_bound.unwrap_or(complete) }
    }
}

/// The guard against a regenerating share that stops advancing.
pub struct Progress {
    paths: u32,
    /// Every path ends within `max_depth` iterations of its start and a free slot is refilled
    /// at the next iteration, so some sample must finish within this many iterations.
    patience: u32,
    last_finished: u32,
    last_change: u32,
}

impl Progress {
    pub fn new(paths: u32, max_depth: u32, sync_every: u32) -> Self {
        Self {
            paths,
            patience: max_depth.saturating_add(sync_every).saturating_add(1),
            last_finished: 0,
            last_change: 0,
        }
    }

    /// An error if, after `iterations`, no sample has finished for longer than any path can take
    /// (a scheduling bug, never a slow scene); none once all `paths` samples have finished.
    pub fn check(&mut self, finished: u32, iterations: u32) -> Result<()> {
        if finished >= self.paths {
            return Ok(());
        }
        if finished != self.last_finished {
            self.last_finished = finished;
            self.last_change = iterations;
        } else if iterations - self.last_change > self.patience {
            bail!(
                "the regenerating wavefront stalled: {finished} of {} samples finished, none in the \
                 last {} iterations",
                self.paths,
                iterations - self.last_change
            );
        }
        Ok(())
    }
}

/// Slots refilled where their paths ended (`--refill in-place`), by the pass they ended in.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RefilledInPlace {
    pub intersect: u64,
    pub shade: u64,
}

/// What a render's schedule cost, for run reports.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ScheduleStats {
    pub schedule: Schedule,
    /// Iterations between read-backs (regenerate only).
    pub sync_every: Option<u32>,
    /// Waves, or chunks (of one pool of samples) when regenerating.
    pub shares: u64,
    /// Iterations recorded (bounces × waves, or refill-and-bounce rounds).
    pub iterations: u64,
    /// Iterations that found no ray to trace: in waves the bounces no path reached, when
    /// regenerating the ones recorded after the chunk's work ran out.
    pub idle_iterations: u64,
    /// Compute passes dispatched, empty ones included.
    pub dispatches: u64,
    /// Indirect dispatches sized to zero workgroups (their fixed cost bought nothing).
    pub empty_dispatches: u64,
    /// Mean over intersect passes of the paths they traced ÷ the pool.
    pub intersect_occupancy: f64,
    /// Megakernel tail passes (`--tail megakernel`: at most one per chunk).
    pub tail_passes: u64,
    /// Paths the tail passes finished.
    pub tail_paths: u64,
    /// With the scan compaction: whether its workgroup scan used subgroup operations.
    pub subgroup_scan: Option<bool>,
    /// Whether queue appends were aggregated per subgroup (`--append`).
    pub subgroup_append: bool,
    /// Whether the ray queue was kept in slot order (`--queue-order`, `auto` resolved).
    #[serde(default)]
    pub slot_order: bool,
    /// Whether that slot order was keyed by depth (`slot-depth`).
    #[serde(default)]
    pub depth_key: bool,
    /// Regenerating: the live fraction of the pool at or below which refills ran (`--refill-below`).
    #[serde(default)]
    pub refill_below: Option<f64>,
    /// Regenerating: whether live states were compacted before refills (`--compact-states`).
    #[serde(default)]
    pub compact_states: Option<bool>,
    /// Compactions run (refills with `--compact-states on`) and path states they moved.
    #[serde(default)]
    pub compactions: u64,
    #[serde(default)]
    pub states_moved: u64,
    /// The key the ray queue was sorted by before each intersect (`--ray-sort`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ray_sort: Option<String>,
    /// Read-backs inside a share's loop that the host waited for with no newer batch queued
    /// (the GPU idle meanwhile): 0 where the host runs ahead (`--schedule regenerate` without
    /// per-pass timestamps; waves never read back inside the loop).
    #[serde(default)]
    pub blocking_reads: u64,
    /// Waits for an older batch's read-back while newer ones were queued (the host at its bound
    /// of batches in flight; the GPU kept busy).
    #[serde(default)]
    pub throttles: u64,
    /// Regenerating: iterations recorded past a share's end (the host had not yet read that it
    /// was done); they dispatch zero workgroups and are counted nowhere else.
    #[serde(default)]
    pub speculative_iterations: u64,
    /// The dispatches those iterations recorded (not in `dispatches`).
    #[serde(default)]
    pub speculative_dispatches: u64,
    /// Regenerating with `--refill in-place`: slots that took their next sample where their path
    /// ended, in intersect (an escape) and in shade; the refill pass started the others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refilled_in_place: Option<RefilledInPlace>,
    /// Bytes of path state the passes read and wrote, modelled from the queue counts
    /// ([`super::traffic`]; with compaction, whose queues are counted).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state_traffic: Option<super::traffic::StateTraffic>,
    /// Entries queued on each queue (`QUEUE_COUNT` regions), summed over bounces and shares.
    #[serde(skip)]
    pub queued: [u64; QUEUE_COUNT as usize],
    /// Regenerating with camera rays made in place: camera rays that hit, and paths that went on
    /// from that hit (`COUNTER_CAMERA_HITS`, `COUNTER_FIRST_CONTINUING`), summed over shares.
    #[serde(skip)]
    pub first_bounce: (u64, u64),
    #[serde(skip)]
    intersected: u64,
    #[serde(skip)]
    pool: u32,
}

impl ScheduleStats {
    pub fn new(schedule: Schedule, sync_every: u32, pool: u32) -> Self {
        Self {
            schedule,
            sync_every: (schedule == Schedule::Regenerate).then_some(sync_every),
            shares: 0,
            iterations: 0,
            idle_iterations: 0,
            dispatches: 0,
            empty_dispatches: 0,
            intersect_occupancy: 0.0,
            tail_passes: 0,
            tail_paths: 0,
            subgroup_scan: None,
            subgroup_append: false,
            slot_order: false,
            depth_key: false,
            refill_below: None,
            compact_states: None,
            compactions: 0,
            states_moved: 0,
            ray_sort: None,
            blocking_reads: 0,
            throttles: 0,
            speculative_iterations: 0,
            speculative_dispatches: 0,
            refilled_in_place: None,
            state_traffic: None,
            queued: [0; QUEUE_COUNT as usize],
            first_bounce: (0, 0),
            intersected: 0,
            pool,
        }
    }

    /// Adds a share's queue counts per bounce (`rows` × `QUEUE_COUNT` words from
    /// `COUNTER_STATS`, recorded with compaction only).
    pub fn add_rows(&mut self, rows: &[u32]) {
        for row in rows.chunks_exact(QUEUE_COUNT as usize) {
            for (total, &n) in self.queued.iter_mut().zip(row) {
                *total += n as u64;
            }
        }
    }

    /// Adds a finished share of `units` waves or chunks (`iterations` recorded, `dispatches`
    /// passes), reading the GPU's counters back now, and zeroes them, so they never overflow on
    /// long renders. (Waves copy them into a [`super::share_ledger::ShareLedger`] instead.)
    pub fn add_share(
        &mut self,
        ctx: &GpuContext,
        state: &PathState,
        units: u32,
        iterations: u32,
        dispatches: u64,
    ) -> Result<()> {
        let words: Vec<u32> = read_back(ctx, &state.counters, (COUNTER_SCHEDULE + word::WORDS) * 4)?;
        self.add_share_words(ctx, &words[COUNTER_SCHEDULE as usize..], units, iterations, dispatches)?;
        let rows = state.stats_bounces as u64 * QUEUE_COUNT;
        self.add_rows(&words[COUNTER_STATS as usize..(COUNTER_STATS + rows) as usize]);
        // The bounce-0 counts in the row after the share's (regenerating: one row).
        let hits = (COUNTER_STATS + rows) as usize;
        self.first_bounce.0 += words[hits] as u64;
        self.first_bounce.1 += words[hits + 1] as u64;
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&state.counters, COUNTER_STATS * 4, Some((rows + QUEUE_COUNT) * 4));
        clear_share_counters(&mut enc, state);
        ctx.queue.submit([enc.finish()]);
        Ok(())
    }

    /// [`Self::add_share`] from the scheduling counters (`schedule`: the words from
    /// `COUNTER_SCHEDULE`) as a share left them.
    pub fn add_share_words(
        &mut self,
        ctx: &GpuContext,
        schedule: &[u32],
        units: u32,
        iterations: u32,
        dispatches: u64,
    ) -> Result<()> {
        let w = |i: usize| schedule[i] as u64;
        if w(word::CLAMPED) > 0 {
            bail!(
                "{} indirect dispatches were sized past {}'s limit of {} workgroups and clamped: a \
                 queue grew past the pool (a bug; please report it with `wavetrace info`)",
                w(word::CLAMPED),
                ctx.summary.name,
                ctx.summary.max_compute_workgroups_per_dimension
            );
        }
        if w(word::COMPACT_MISMATCH) > 0 {
            bail!(
                "{} state compactions found the free list and the ray queue disagreeing about the live \
                 paths (nothing was moved; a bug, please report it with `wavetrace info`)",
                w(word::COMPACT_MISMATCH)
            );
        }
        self.shares += units as u64;
        self.compactions += w(word::COMPACTIONS);
        // (regenerate) Counted on the GPU by the decision pass.
        self.tail_passes += w(word::TAIL_PASSES);
        self.tail_paths += w(word::TAIL_PATHS);
        if let Some(r) = &mut self.refilled_in_place {
            r.intersect += w(word::REFILLED_INTERSECT);
            r.shade += w(word::REFILLED_SHADE);
        }
        self.states_moved += w(word::STATES_MOVED);
        self.iterations += iterations as u64;
        self.idle_iterations += w(word::IDLE);
        self.dispatches += dispatches;
        self.empty_dispatches += w(word::EMPTY);
        self.intersected += w(word::INTERSECTED);
        self.intersect_occupancy =
            self.intersected as f64 / (self.iterations.max(1) as f64 * self.pool as f64);
        Ok(())
    }
}

/// Zeroes the scheduling counters a share adds up (from `EMPTY` on), for the next share.
pub fn clear_share_counters(enc: &mut wgpu::CommandEncoder, state: &PathState) {
    let first = (COUNTER_SCHEDULE + word::EMPTY as u64) * 4;
    enc.clear_buffer(&state.counters, first, Some((word::WORDS - word::EMPTY as u64) * 4));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The host's rule after a check, on a share of 4 chunks of 1000 in a ring of 2.
    #[test]
    fn the_decision_after_a_check() {
        let r = Ring::new(4000, 1000, 2000);
        assert_eq!((r.chunk, r.ring, r.chunks()), (1000, 2, 4));
        let counters = |started, ring: [u32; 2], before_ring| ChunkCounters {
            started,
            finished: before_ring + ring.iter().sum::<u32>(),
            ring: ring.to_vec(),
        };
        // Without the tail: the complete chunks go into the film; refills go on.
        let c = counters(2000, [1000, 500], 0);
        let d = Decision::after(&r, &c, 0, 1000, 1000, None);
        assert_eq!(d, Decision { refill: true, complete: 1, tail_bound: None, added: 1 });
        // With the tail, at the share's end: every sample started and few left, so it takes all.
        let c = counters(4000, [990, 995], 2000);
        let d = Decision::after(&r, &c, 2, 3000, 1000, Some(0.05));
        assert_eq!(d, Decision { refill: false, complete: 2, tail_bound: Some(4), added: 4 });
        // Mid-share: the oldest chunk, nearly done, is finished by the tail so that the next
        // refills (another 1000 expected) need not stop at the ring's end.
        let c = counters(2000, [990, 0], 0);
        let d = Decision::after(&r, &c, 0, 1000, 1000, Some(0.05));
        assert_eq!(d, Decision { refill: true, complete: 0, tail_bound: Some(1), added: 1 });
        // Without the tail the same check adds nothing.
        assert_eq!(Decision::after(&r, &c, 0, 1000, 1000, None).added, 0);
    }

    /// The arithmetic, not a render: at 1920x1080 and 4096 spp, for any max depth the settings
    /// accept, every share of either schedule holds few enough samples that a counter adding up
    /// to max_depth + 1 per sample stays within u32 (the pool here as large as a 4 GiB binding
    /// of 96-byte paths allows).
    #[test]
    fn no_share_counter_can_wrap_at_1080p_4096spp() {
        let (pixels, spp) = (1920 * 1080, 4096);
        let pool = ((4u64 << 30) / 96) as u32;
        // The deepest the settings accept still leaves shares of one sample or more.
        assert!(counter_safe_share((1 << 24) - 1) >= 1);
        for max_depth in [1, 8, 50, 1000, 65_536] {
            for schedule in [RunSchedule::Waves, RunSchedule::Regenerate] {
                let name = format!("{schedule:?}");
                let plan = shares(schedule, pixels, spp, pool, max_depth);
                let total: u64 = plan.iter().map(|d| d.pixel_count as u64 * d.sample_count as u64).sum();
                assert_eq!(total, pixels as u64 * spp as u64, "{name}: every sample planned");
                for d in &plan {
                    let worst = d.pixel_count as u64 * d.sample_count as u64 * (max_depth as u64 + 1);
                    assert!(worst <= u32::MAX as u64, "{name} depth {max_depth}: {d:?} can count {worst}");
                }
            }
        }
        // Without the bound, the regenerating share at depth 50 could count past 2^32.
        assert!(MAX_SHARE * 51 > u32::MAX as u64);
    }

    #[test]
    fn ring_chunks_cover_the_share() {
        // 10 000 samples, a pool of 1 024 and room for 4 pools: 10 chunks, the last of 784.
        let r = Ring::new(10_000, 1024, 4 * 1024);
        assert_eq!((r.chunk, r.ring, r.chunks(), r.samples()), (1024, 4, 10, 4096));
        assert_eq!((r.len(0), r.len(9), r.end(9)), (1024, 784, 10_000));
        // Refills run at most four chunks ahead of the oldest not yet in the film.
        assert_eq!((r.fill_limit(0), r.fill_limit(5), r.fill_limit(6)), (4096, 9216, 10_000));
        // A share smaller than the ring: one chunk per pool, a ring of as many.
        let small = Ring::new(3000, 1024, 8 * 1024);
        assert_eq!((small.ring, small.chunks(), small.fill_limit(0)), (3, 3, 3000));
        // A share smaller than the pool: one chunk.
        let one = Ring::new(500, 1024, 8 * 1024);
        assert_eq!((one.chunk, one.ring, one.chunks(), one.len(0)), (500, 1, 1, 500));
    }

    #[test]
    fn complete_chunks_are_taken_in_order() {
        let r = Ring::new(10_000, 1024, 4 * 1024);
        // Chunks 4..8 in flight (ring slots 0, 1, 2, 3): 4 and 5 done, 6 not, 7 done.
        let finished = [1024, 1024, 1000, 1024];
        assert_eq!(r.complete_from(4, &finished), 6);
        assert_eq!(r.complete_from(6, &finished), 6);
        // The short last chunk is complete at its own length.
        assert_eq!(r.complete_from(9, &[0, 784, 0, 0]), 10);
        // A ring slot counts only the chunk that holds it now: chunks 2..6 all complete, chunk 6
        // (slot 2 again) not started, however full slot 2 looks.
        assert_eq!(r.complete_from(2, &[1024, 1024, 1024, 1024]), 6);
    }

    #[test]
    fn the_tail_flushes_only_what_the_ring_needs_back() {
        let r = Ring::new(100_000, 1000, 4000);
        // Chunks 0..4 in flight, 3 500 samples started: a batch starting 1 000 more would stop at
        // the ring's end (4 000). Chunk 0 has 20 paths left, chunk 1 has 600.
        let finished = [980, 400, 0, 0];
        assert_eq!(r.flush_to(0, 3500, 1000, &finished, 50.0), 1, "chunk 0 only: chunk 1 has too many left");
        // With room for the batch, nothing is flushed.
        assert_eq!(r.flush_to(0, 2500, 1000, &finished, 50.0), 0);
        // A chunk whose samples have not all started is never flushed.
        assert_eq!(r.flush_to(0, 900, 5000, &[880, 0, 0, 0], 50.0), 0);
        // Where the ring reaches the share's end, the final tail finishes what is left instead.
        let end = Ring::new(4500, 1000, 4000);
        assert_eq!(end.flush_to(1, 4400, 1000, &[1000, 990, 0, 0, 0], 50.0), 1);
    }
}
