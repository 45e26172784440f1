//! What drives a share: one method per schedule records its iterations (waves: one per bounce;
//! regenerating: batches submitted ahead, their counters read back through a ring of staging
//! buffers without waiting, until one says the share is done).

use super::super::buffers::{self, Staging};
use super::super::context::GpuContext;
use super::graph::Phase;
use super::path_state::schedule_word as word;
use super::recorder::{Bindings, WaveRecorder};
use super::share_ledger::{ShareLedger, ShareWork};
use super::stages::Stages;
use super::{schedule, QueueHistogram, ScheduleStats, WavefrontOptions};
use anyhow::{bail, Result};

/// What drives every share of a render: its passes, bindings and options. One method per
/// schedule records a share's iterations and returns how many it recorded.
pub(super) struct Drive<'a> {
    pub(super) ctx: &'a GpuContext,
    pub(super) stages: &'a Stages<'a>,
    pub(super) b: &'a Bindings,
    pub(super) opts: &'a WavefrontOptions,
    pub(super) max_depth: u32,
    pub(super) pool: u32,
}

impl Drive<'_> {
    /// Waves: one iteration per bounce, the wave's paths all starting together.
    pub(super) fn waves(&self, wave: &mut WaveRecorder<'_>) -> Result<u32> {
        for bounce in 0..self.max_depth {
            if wave.timer.remaining() < self.stages.graph.per_iteration() + 1 {
                wave.submit_and_wait(self.ctx)?;
            }
            self.stages.record(wave, Phase::Iteration, bounce, false, false);
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
    pub(super) fn regenerate(
        &self,
        wave: &mut WaveRecorder<'_>,
        r: &schedule::Ring,
        staging: &[Staging],
        stats: &mut ScheduleStats,
        progress: &dyn Fn(u64),
    ) -> Result<u32> {
        let (ctx, state) = (self.ctx, &self.b.state);
        let tail = self.stages.graph.phase(Phase::Decided).any(|p| p.label == crate::gpu::label::TAIL);
        self.start_share(r, tail);
        let mut stall = schedule::Progress::new(r.paths, self.max_depth, self.opts.sync_every);
        // Whether the first refill starts every sample (it starts a pool of them, up to the
        // ring's end): then later iterations record no refill passes.
        let one_refill = r.paths <= self.pool.min(r.fill_limit(0));
        let bytes = schedule::ChunkCounters::bytes(r);
        let mut pending = std::collections::VecDeque::new();
        let mut next_staging = 0;
        // The dispatches and compute passes recorded up to each iteration's end (its decision
        // passes included): the share's own counts once the GPU says how many it ran.
        let mut dispatches_at = Vec::new();
        let mut ran = None;
        // Reads a batch's counters back once mapped: Some(iterations) when the share is done.
        let mut read = |req: buffers::MapRequest, k: usize| -> Result<Option<u32>> {
            let words: Vec<u32> = staging[k].take(&req)?;
            let (c, back) = schedule::ChunkCounters::parse(&words, r);
            let (added, chunks) = (back.oldest, r.chunks());
            if back.failed {
                bail!(
                    "the regenerating wavefront finished every sample but added {added} of {chunks} chunks"
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
            self.record_batch(wave, tail, one_refill, &mut dispatches_at)?;
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
        own_counts(wave, stats, ran, &dispatches_at)?;
        Ok(ran)
    }

    /// (regenerate) Records one batch of `--sync-every` iterations after the `dispatches_at.len()`
    /// recorded so far, pushing each one's dispatch and compute-pass counts.
    fn record_batch(
        &self,
        wave: &mut WaveRecorder<'_>,
        tail: bool,
        one_refill: bool,
        dispatches_at: &mut Vec<(u64, u64)>,
    ) -> Result<()> {
        let sync_every = self.opts.sync_every;
        for _ in 0..sync_every {
            let recorded = dispatches_at.len() as u32;
            if wave.timer.remaining() < self.stages.graph.per_iteration() + 1 {
                wave.submit_and_wait(self.ctx)?;
            }
            // With the tail the GPU may check after any iteration (every one once every sample
            // has started), so it decides after each; else after every batch.
            let decide = tail || (recorded + 1).is_multiple_of(sync_every);
            self.stages.record(wave, Phase::Iteration, recorded, recorded == 0 || !one_refill, decide);
            if decide {
                self.stages.record(wave, Phase::Decided, recorded, false, false);
            }
            dispatches_at.push((wave.dispatches, wave.compute_passes));
        }
        Ok(())
    }

    /// (regenerate) The decision pass's knobs and the refills' first limit, written before a
    /// share; its own words start at zero (the buffer's creation, or the clear after the last
    /// share).
    fn start_share(&self, r: &schedule::Ring, tail: bool) {
        let (ctx, state) = (self.ctx, &self.b.state);
        state.write_schedule_word(ctx, word::FILL_LIMIT, r.fill_limit(0));
        state.write_schedule_word(ctx, word::TAIL_BOUND, 0);
        state.write_schedule_word(ctx, word::SYNC_EVERY, self.opts.sync_every);
        state.write_schedule_word(ctx, word::TAIL_ON, tail as u32);
        // `Decision::after` compares a path count with threshold × pool: for whole counts, the
        // same as comparing with its floor.
        let max_live = (self.opts.tail_threshold * self.pool as f64).floor() as u32;
        state.write_schedule_word(ctx, word::TAIL_MAX_LIVE, max_live);
    }

    /// (waves) A wave's end: its radiance into the film, its counters copied into the share
    /// ledger on the GPU (per wave, so the GPU's u32 counters never overflow on long renders),
    /// and submitted without waiting, but for the `last` wave or a full ledger, which are waited
    /// for and drained into `stats` and the histogram.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn end_wave(
        &self,
        wave: &mut WaveRecorder<'_>,
        iterations: u32,
        ledger: &mut ShareLedger,
        last: bool,
        stats: &mut ScheduleStats,
        histogram: Option<&mut QueueHistogram>,
    ) -> Result<()> {
        self.stages.record(wave, Phase::End, iterations, false, false);
        let work = ShareWork { units: 1, iterations, dispatches: wave.dispatches };
        ledger.record(wave.encoder().0, &self.b.state, work);
        if last || ledger.is_full() {
            wave.submit_and_wait(self.ctx)?;
            ledger.drain(self.ctx, stats, histogram)?;
        } else {
            wave.submit(self.ctx)?;
        }
        Ok(())
    }
}

/// (regenerate) The share's own counts once the GPU says it ran `ran` of the iterations
/// recorded (`at`: the dispatches and compute passes recorded up to each one's end): those
/// recorded past it are counted as speculative.
fn own_counts(
    wave: &mut WaveRecorder<'_>,
    stats: &mut ScheduleStats,
    ran: u32,
    at: &[(u64, u64)],
) -> Result<()> {
    let recorded = at.len() as u32;
    if ran == 0 || ran > recorded {
        bail!("the regenerating wavefront's GPU counted {ran} iterations of the {recorded} recorded");
    }
    stats.speculative_iterations += (recorded - ran) as u64;
    let (own, own_passes) = at[ran as usize - 1];
    stats.speculative_dispatches += wave.dispatches - own;
    wave.dispatches = own;
    wave.compute_passes = own_passes;
    Ok(())
}
