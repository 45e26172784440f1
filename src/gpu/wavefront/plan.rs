//! A render's plan: what runs, decided once before anything is recorded — the pool, the
//! schedule's shares and sample ring, the queue order and scan the adapter allows, which shade
//! passes and which optional stages run, and the per-slot buffers the pool holds.

use super::super::context::GpuContext;
use super::path_state::{self, PoolLayout};
use super::{pool, refill, schedule, traffic, ScheduleStats};
use super::{
    Append, CompactStates, Compaction, ComputePasses, QueueOrder, RaySort, Refill, RunSchedule, Scan,
    ShadePasses, ShadowRays, WavefrontOptions,
};
use crate::layout::material_kind::COUNT as KINDS;
use crate::layout::DispatchParams;
use crate::layout::WaveUniform;
use crate::options::wavefront as knob;
use crate::options::{Named, PoolSize};
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::Result;

/// Bounce histogram rows kept; deeper bounces are added to the last row.
pub const STATS_BOUNCES: u32 = path_state::MAX_STATS_BOUNCES as u32;

pub struct Plan {
    pub schedule: RunSchedule,
    pub regenerate: bool,
    /// Paths in flight: `--pool-size` as the adapter allows, at most the job's samples.
    pub pool: u32,
    /// `--queue-order` with `auto` resolved for this job.
    pub queue_order: QueueOrder,
    pub subgroup_scan: bool,
    pub subgroup_append: bool,
    /// The image's samples cut into shares (waves of at most a pool; regenerating, as large as
    /// a dispatch's parameters allow).
    pub shares: Vec<DispatchParams>,
    /// The material kinds with a shade pass (or queue) and, with `--shade per-texture`, the
    /// costly patterns with one.
    pub kinds: Vec<u32>,
    pub patterns: Vec<u32>,
    /// Regenerating: the sample ring every share uses (one pool per chunk).
    pub ring: schedule::Ring,
    /// Camera rays made where they are used, not stored (queues on, no ray sort).
    pub camera_in_place: bool,
    /// Regenerating with `--refill in-place` (the `REFILL_IN_PLACE` pipeline constant).
    pub refill_in_place: bool,
    /// The job's numbers as the shaders read them.
    pub wave: WaveUniform,
    /// The knobs as the shaders' pipeline constants (`knob_constants`).
    knobs: Vec<(&'static str, f64)>,
    /// Rows of the bounce histogram (one when regenerating: queues mix bounces).
    pub stats_bounces: u32,
    /// `--nee on` in a scene with lights, its shadow rays traced by a pass of their own.
    pub shadow_pass: bool,
    /// `--nee on` in a scene with lights, its shadow rays traced in shade (`--shadow-rays
    /// inline`).
    pub inline_shadow: bool,
    /// Slot order with atomic appends: a sweep over the pool after shade.
    pub uses_sweep: bool,
    /// The scan passes: the scan method's, or the depth key's over the pool after shade.
    pub uses_scan: bool,
    /// The scan method builds the material queues after intersect too.
    pub scan_materials: bool,
    /// (regenerate) `--compact-states on`: the state compaction's passes before each refill.
    pub compact_states: bool,
    /// `--ray-sort`: the origin-cell bits per axis of its key (0: the octant alone).
    pub ray_sort_cell_bits: Option<u32>,
    /// Workgroups of the scan's pass over its block totals (`compact_blocks`).
    pub scan_blocks: u32,
    pub layout: PoolLayout,
}

/// The shade passes' queue bits: one per material kind's pass, then one per pattern's; none for
/// the sorted pass (queue_setup_shade counts it itself).
fn shade_mask(shade: ShadePasses, kinds: &[u32], patterns: &[u32]) -> u32 {
    match shade {
        ShadePasses::Single => 1,
        ShadePasses::Sorted => 0,
        ShadePasses::PerMaterial | ShadePasses::PerTexture => {
            kinds.iter().fold(0, |m, k| m | 1 << k)
                | patterns.iter().fold(0, |m, p| m | 1 << (KINDS as u32 + p))
        }
    }
}

impl Plan {
    /// The plan of `opts` (resolved: `schedule` is what runs) for this scene and job.
    pub fn new(
        ctx: &GpuContext,
        scene: &PackedScene,
        settings: &RenderSettings,
        opts: &WavefrontOptions,
        schedule: RunSchedule,
    ) -> Result<Plan> {
        ctx.check_workgroup_size(opts.workgroup_size)?;
        // A job smaller than the pool needs no more slots than samples: passes over the whole
        // pool (the regenerating schedule's start, compaction off) and its memory shrink with it.
        let pool = pool::choose(ctx, opts)?.min(u32::try_from(settings.sample_count()).unwrap_or(u32::MAX));
        let queue_order =
            opts.queue_order.resolve(opts.schedule, opts.compaction, settings.sample_count(), pool);
        let subgroup_scan = opts.scan.uses_subgroups(ctx)?;
        let subgroup_append = opts.append.uses_subgroups(ctx)?;
        let regenerate = schedule == RunSchedule::Regenerate;
        let pixels = settings.width * settings.height;
        let shares = schedule::shares(schedule, pixels, settings.spp, pool, settings.max_depth);
        let per_texture = opts.shade == ShadePasses::PerTexture;
        // Per-texture: the patterns' passes, and the material kinds' passes for what is left.
        let (kinds, patterns) =
            if per_texture { scene.shade_classes() } else { (scene.material_kinds_used(), vec![]) };
        // Regenerating: every share's sample ring has the same chunks (one pool) and at most the
        // same number of them, so one ring buffer serves them all.
        let ring_budget = schedule::ring_budget(ctx, pool, opts.chunk_pools);
        let largest_share = shares.iter().map(|d| d.pixel_count * d.sample_count).max().unwrap_or(1);
        let ring = schedule::Ring::new(largest_share, pool, ring_budget);
        // Camera rays made where they are used (wavefront/shared/path_camera.wgsl) need queues
        // (a pass over the whole pool tells live slots by their stored direction) and no ray
        // sort (whose keys read the stored ray).
        let camera_in_place = opts.compaction != Compaction::Off && opts.ray_sort == RaySort::Off;
        let wave = WaveUniform {
            pool,
            chunk: if regenerate { ring.chunk } else { 0 },
            ring: if regenerate { ring.ring } else { 0 },
            refill_live: refill::refill_live(opts.refill_below, pool),
        };
        let flag = |on: bool| on as u32 as f64;
        let knobs = vec![
            ("REGENERATE", flag(regenerate)),
            knob::refill::constant(opts, regenerate),
            knob::compaction::constant(opts),
            knob::shade::constant(opts),
            ("SHADE_MASK", shade_mask(opts.shade, &kinds, &patterns) as f64),
            ("QUEUE_ORDER", queue_order.word() as f64),
            knob::compact_states::constant(opts),
            ("CAMERA_IN_PLACE", flag(camera_in_place)),
            knob::launch::constant(opts),
        ];
        let lit = settings.nee && !scene.lights.is_empty();
        let shadow_pass = lit && opts.shadow_rays == ShadowRays::Pass;
        // The scan passes: the scan method's, or the depth key's over the pool after shade; slot
        // order with atomic appends sweeps the pool instead (slot_sweep.wgsl).
        let uses_sweep = queue_order == QueueOrder::Slot && opts.compaction == Compaction::Atomic;
        let uses_scan = opts.compaction == Compaction::Scan || (queue_order.is_slot() && !uses_sweep);
        let layout = PoolLayout {
            targets: uses_scan || uses_sweep,
            scan: uses_scan,
            shadow: shadow_pass,
            ring_samples: regenerate.then_some(ring.samples() as u64),
            pattern_queues: per_texture,
        };
        Ok(Plan {
            schedule,
            regenerate,
            pool,
            queue_order,
            subgroup_scan,
            subgroup_append,
            shares,
            kinds,
            patterns,
            ring,
            camera_in_place,
            refill_in_place: regenerate && opts.refill == Refill::InPlace,
            wave,
            knobs,
            stats_bounces: if regenerate { 1 } else { settings.max_depth.min(STATS_BOUNCES) },
            shadow_pass,
            inline_shadow: lit && opts.shadow_rays == ShadowRays::Inline,
            uses_sweep,
            uses_scan,
            scan_materials: opts.compaction == Compaction::Scan,
            compact_states: regenerate && opts.compact_states == CompactStates::On,
            ray_sort_cell_bits: (opts.ray_sort != RaySort::Off).then(|| opts.ray_sort.cell_bits()),
            scan_blocks: path_state::scan_block_groups(pool as u64) as u32,
            layout,
        })
    }

    /// The knobs as pipeline constants, which every pass over the path state declares
    /// (path_state.wgsl).
    pub fn knob_constants(&self) -> Vec<(&'static str, f64)> {
        self.knobs.clone()
    }

    /// The schedule's record, with what this plan resolved.
    pub fn schedule_stats(&self, opts: &WavefrontOptions) -> ScheduleStats {
        let mut stats = ScheduleStats::new(self.schedule.into(), opts.sync_every, self.pool);
        stats.subgroup_scan = self.uses_scan.then_some(self.subgroup_scan);
        stats.subgroup_append = self.subgroup_append;
        stats.slot_order = self.queue_order.is_slot();
        stats.depth_key = self.queue_order == QueueOrder::SlotDepth;
        stats.ray_sort = Some(opts.ray_sort.name());
        if self.regenerate {
            stats.refill_below = Some(opts.refill_below);
            stats.compact_states = Some(opts.compact_states == CompactStates::On);
            stats.refilled_in_place = self.refill_in_place.then(Default::default);
        }
        stats
    }

    /// What the path-state traffic model needs to know of the passes that run.
    pub fn traffic_shape(&self, opts: &WavefrontOptions) -> traffic::Shape {
        traffic::Shape {
            layout: self.layout,
            regenerate: self.regenerate,
            atomic: opts.compaction == Compaction::Atomic,
            slot_order: self.queue_order.is_slot(),
            sweep: self.uses_sweep,
            camera_in_place: self.camera_in_place,
            inline_shadow: self.inline_shadow,
        }
    }

    /// The options as they ran: every knob resolved at run time made concrete (`shared`:
    /// whether dispatches shared compute passes).
    pub fn resolved(&self, opts: &WavefrontOptions, shared: bool) -> WavefrontOptions {
        WavefrontOptions {
            pool_size: Some(PoolSize::Paths(self.pool)),
            queue_order: self.queue_order,
            scan: if self.subgroup_scan { Scan::Subgroup } else { Scan::Workgroup },
            append: if self.subgroup_append { Append::Subgroup } else { Append::Lane },
            compute_passes: if shared { ComputePasses::Shared } else { ComputePasses::PerDispatch },
            ..*opts
        }
    }
}
