//! The passes of a render, built once from its [`Plan`](super::plan::Plan), and one iteration's
//! recording of them (the loop body of the module's pseudocode).

use super::super::accumulate::Accumulate;
use super::super::context::GpuContext;
use super::super::memory::MemoryLedger;
use super::compact::Target;
use super::plan::Plan;
use super::recorder::{Bindings, WaveRecorder};
use super::{
    compact, compact_states, generate, intersect, queue_setup, ray_sort, shade, shadow, slot_sweep, tail,
};
use super::{CompactStates, Compaction, RaySort, Tail, WavefrontOptions};
use anyhow::Result;

/// The passes of a render, recorded per share and per iteration.
pub(super) struct Stages {
    pub(super) generate: generate::Generate,
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
    pub(super) tail: Option<tail::TailPass>,
    /// `--compact-states on`: before each refill.
    compact_states: Option<compact_states::CompactStatesPasses>,
    /// `--ray-sort`: between queue_setup_intersect and intersect.
    ray_sort: Option<ray_sort::RaySortPasses>,
    regenerate: bool,
}

impl Stages {
    /// The passes `plan` runs, their pipelines built (or taken from the device's cache).
    pub(super) fn new(
        ctx: &GpuContext,
        plan: &Plan,
        b: &Bindings,
        accumulate: &Accumulate,
        opts: &WavefrontOptions,
        instrument: bool,
        memory: &mut MemoryLedger,
    ) -> Result<Stages> {
        let wg = opts.workgroup_size;
        let regenerate = plan.regenerate;
        Ok(Stages {
            generate: generate::Generate::new(ctx, b, plan.schedule, plan.pool, wg, instrument)?,
            queue_setup: queue_setup::QueueSetup::new(
                ctx,
                b,
                wg,
                regenerate.then(|| accumulate.range_buffer()),
            )?,
            intersect: intersect::Intersect::new(ctx, b, wg, instrument)?,
            shade: shade::Shade::new(ctx, b, plan, opts.shade, wg, instrument)?,
            compact: plan.uses_scan.then(|| compact::Compact::new(ctx, b, plan.subgroup_scan)).transpose()?,
            slot_sweep: plan.uses_sweep.then(|| slot_sweep::SlotSweep::new(ctx, b)).transpose()?,
            shadow: plan.shadow_pass.then(|| shadow::Shadow::new(ctx, b, wg, instrument)).transpose()?,
            tail: (opts.tail == Tail::Megakernel)
                .then(|| tail::TailPass::new(ctx, b, wg, instrument))
                .transpose()?,
            compact_states: (opts.compact_states == CompactStates::On)
                .then(|| compact_states::CompactStatesPasses::new(ctx, b, wg))
                .transpose()?,
            ray_sort: (opts.ray_sort != RaySort::Off)
                .then(|| ray_sort::RaySortPasses::new(ctx, b, wg, opts.ray_sort, memory))
                .transpose()?,
            scan_materials: opts.compaction == Compaction::Scan,
            regenerate,
        })
    }

    /// One iteration: a bounce of every path in waves; when regenerating, a refill (while the
    /// share has samples left to start) and then a bounce of every path in the pool, whatever
    /// its depth.
    /// `decide` (regenerate): the iteration ends with the schedule's decision pass (with NEE
    /// folded into queue_setup_shadow); the caller records the passes it sizes after.
    pub(super) fn record_iteration(&self, wave: &mut WaveRecorder<'_>, i: u32, refill: bool, decide: bool) {
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
    pub(super) fn per_iteration(&self) -> usize {
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
