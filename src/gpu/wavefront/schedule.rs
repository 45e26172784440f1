//! How the wavefront schedules its pool (`--schedule`), and what the schedule cost: dispatches
//! (empty ones apart), iterations (idle ones apart) and the intersect passes' occupancy, read
//! from the scheduling counters of `shaders/shared/path_state.wgsl`.

use super::super::buffers::read_back;
use super::super::context::GpuContext;
use super::path_state::{schedule_word as word, PathState, COUNTER_SCHEDULE};
use anyhow::{bail, Result};

pub use super::super::schedule::Schedule;

/// Iterations between read-backs when regenerating: a read-back makes the host wait for the
/// GPU; each iteration recorded after the work ran out costs its (empty) dispatches.
pub const DEFAULT_SYNC_EVERY: u32 = 8;
/// Most iterations between read-backs.
pub const MAX_SYNC_EVERY: u32 = 1024;
/// Default `--chunk-pools`: a chunk holds at most this many pools of samples. Its per-sample
/// radiance buffer (16 bytes a sample) costs this many times the pool's radiance, and the pool
/// drains once per chunk.
pub const CHUNK_POOLS: u32 = 8;
/// Most pools a chunk may hold.
pub const MAX_CHUNK_POOLS: u32 = 1024;

pub fn check_sync_every(k: u32) -> Result<()> {
    if !(1..=MAX_SYNC_EVERY).contains(&k) {
        bail!("--sync-every must be in 1..={MAX_SYNC_EVERY} iterations, got {k}");
    }
    Ok(())
}

pub fn check_chunk_pools(n: u32) -> Result<()> {
    if !(1..=MAX_CHUNK_POOLS).contains(&n) {
        bail!("--chunk-pools must be in 1..={MAX_CHUNK_POOLS} pools, got {n}");
    }
    Ok(())
}

/// Samples per chunk: `chunk_pools` pools, within one storage binding of 16-byte samples.
pub fn chunk_budget(ctx: &GpuContext, pool: u32, chunk_pools: u32) -> u64 {
    let limit = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size) / 16;
    (chunk_pools as u64 * pool as u64).min(limit).clamp(pool as u64, u32::MAX as u64)
}

/// A regenerating chunk's progress, read back between batches of iterations.
pub struct ChunkCounters {
    /// Samples started (handed to a slot).
    pub started: u32,
    /// Samples whose path has ended.
    pub finished: u32,
}

impl ChunkCounters {
    pub fn read(ctx: &GpuContext, state: &PathState) -> Result<Self> {
        let words: Vec<u32> = read_back(ctx, &state.counters, (COUNTER_SCHEDULE + word::WORDS) * 4)?;
        let w = |i: usize| words[COUNTER_SCHEDULE as usize + i];
        Ok(Self { started: w(word::NEXT_SAMPLE), finished: w(word::FINISHED) })
    }

    /// Paths in flight.
    pub fn live(&self) -> u32 {
        self.started - self.finished
    }

    /// Whether the megakernel tail should finish the chunk of `paths` samples now: every sample
    /// started, and at most `threshold` × `pool` paths still going.
    pub fn tail_due(&self, paths: u32, threshold: f64, pool: u32) -> bool {
        self.started == paths && (self.live() as f64) <= threshold * pool as f64
    }
}

/// When a regenerating chunk is done, and the guard against a schedule that stops advancing.
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

    /// Whether all `paths` samples have finished after `iterations`; an error if none finished
    /// for longer than any path can take (a scheduling bug, never a slow scene).
    pub fn done_after(&mut self, finished: u32, iterations: u32) -> Result<bool> {
        if finished >= self.paths {
            return Ok(true);
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
        Ok(false)
    }
}

/// What a render's schedule cost, for run reports.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ScheduleStats {
    pub schedule: Schedule,
    /// Iterations between read-backs (regenerate only).
    pub sync_every: Option<u32>,
    /// Waves, or chunks when regenerating.
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
            intersected: 0,
            pool,
        }
    }

    /// Counts a tail pass that finished `paths` paths.
    pub fn add_tail(&mut self, paths: u32) {
        self.tail_passes += 1;
        self.tail_paths += paths as u64;
    }

    /// Adds a finished share (`iterations` recorded, `dispatches` passes) and zeroes the GPU's
    /// counters, so they never overflow on long renders.
    pub fn add_share(
        &mut self,
        ctx: &GpuContext,
        state: &PathState,
        iterations: u32,
        dispatches: u64,
    ) -> Result<()> {
        let words: Vec<u32> = read_back(ctx, &state.counters, (COUNTER_SCHEDULE + word::WORDS) * 4)?;
        let w = |i: usize| words[COUNTER_SCHEDULE as usize + i] as u64;
        self.shares += 1;
        self.iterations += iterations as u64;
        self.idle_iterations += w(word::IDLE);
        self.dispatches += dispatches;
        self.empty_dispatches += w(word::EMPTY);
        self.intersected += w(word::INTERSECTED);
        self.intersect_occupancy =
            self.intersected as f64 / (self.iterations.max(1) as f64 * self.pool as f64);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        let first = (COUNTER_SCHEDULE + word::EMPTY as u64) * 4;
        enc.clear_buffer(&state.counters, first, Some((word::WORDS - word::EMPTY as u64) * 4));
        ctx.queue.submit([enc.finish()]);
        Ok(())
    }
}
