//! The path pool and its queues (`shaders/wavefront/shared/path_state.wgsl`, bind group 1): structure of
//! arrays, pbrt-v4 style, so each pass reads only the fields it needs.

use super::super::buffers::{check_size, storage_entry, storage_zeroed, uniform_entry};
use super::super::context::GpuContext;
use super::super::dispatch_plan::DispatchUniforms;
use super::super::memory::{MemoryCategory as Mem, MemoryLedger};
use crate::layout::WaveUniform;
use anyhow::Result;
use wgpu::util::DeviceExt;

/// Where the queues, counters and indirect arguments sit for `kinds` material kinds: a kind
/// adds a material queue (and its histogram column), a shade pass's first scan position and
/// an argument slot, and every slot after those follows; nothing is numbered by hand. Its WGSL
/// twin computes the same slots from `MATERIAL_KIND_COUNT` (wavefront/shared/path_state.wgsl,
/// shared/kinds.wgsl); tests/suite/layout.rs checks both for this build's kinds and one more.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QueueLayout {
    pub kinds: u64,
    /// Queue ids (regions of `queues`, each counted at `counters[id]`): the two ray queues,
    /// one per material kind from `QUEUE_MATERIAL_0`, the shadow queue, the free slots; with
    /// `--shade per-texture`, `PATTERN_QUEUES` more from `queue_count` (`QUEUE_PATTERN_0`).
    pub queue_shadow: u64,
    pub queue_free: u64,
    pub queue_count: u64,
    /// Words of `counters` after the queue counts, the iteration and the scan's positions: the
    /// bounce histogram (`MAX_STATS_BOUNCES` rows of `queue_count`), each shade pass's first
    /// scan position, the scheduling words, the ring's chunks, the pattern queues' counts.
    pub counter_stats: u64,
    pub counter_shade_base: u64,
    pub counter_schedule: u64,
    pub counter_ring: u64,
    pub counter_pattern: u64,
    pub counter_words: u64,
    /// Indirect-argument slots after intersect's and one per material kind: the scan passes,
    /// the shadow pass, the refill, the tail, the state compaction's two passes, the
    /// regenerating accumulate, one per costly pattern (`--shade per-texture`).
    pub args_compact: u64,
    pub args_pattern_0: u64,
    pub args_slots: u64,
}

pub const QUEUE_MATERIAL_0: u64 = 2;
pub const ARGS_INTERSECT: u64 = 0;
pub const ARGS_SHADE_0: u64 = 1;
/// Histogram rows the counters have room for (`COUNTER_SHADE_BASE` follows them).
pub const MAX_STATS_BOUNCES: u64 = 64;
/// Most chunks in the sample ring (`--chunk-pools` is at most this).
pub const MAX_RING_CHUNKS: u64 = 1024;
/// `--shade per-texture`: a queue per costly pattern (`PATTERN_QUEUES`).
pub const PATTERN_QUEUES: u64 = 8;

impl QueueLayout {
    pub const fn new(kinds: u64) -> Self {
        let queue_shadow = QUEUE_MATERIAL_0 + kinds;
        let queue_count = queue_shadow + 2;
        let counter_stats = queue_count + 2;
        let counter_shade_base = counter_stats + MAX_STATS_BOUNCES * queue_count;
        let counter_schedule = counter_shade_base + kinds;
        let counter_ring = counter_schedule + schedule_word::WORDS;
        let counter_pattern = counter_ring + MAX_RING_CHUNKS;
        let args_compact = ARGS_SHADE_0 + kinds;
        // ARGS_COMPACT … ARGS_ACCUMULATE: seven slots.
        let args_pattern_0 = args_compact + 7;
        QueueLayout {
            kinds,
            queue_shadow,
            queue_free: queue_shadow + 1,
            queue_count,
            counter_stats,
            counter_shade_base,
            counter_schedule,
            counter_ring,
            counter_pattern,
            counter_words: counter_pattern + PATTERN_QUEUES,
            args_compact,
            args_pattern_0,
            args_slots: args_pattern_0 + PATTERN_QUEUES,
        }
    }
}

/// This build's layout: one material queue per `layout::material_kind`.
pub const LAYOUT: QueueLayout = QueueLayout::new(crate::layout::material_kind::COUNT as u64);
pub const QUEUE_COUNT: u64 = LAYOUT.queue_count;
pub const QUEUE_SHADOW: u64 = LAYOUT.queue_shadow;
/// Words of `counters` before the bounce histogram (`COUNTER_STATS`).
pub const COUNTER_STATS: u64 = LAYOUT.counter_stats;
/// The scheduling counters (`COUNTER_NEXT_SAMPLE` … `COUNTER_FAILED`): the host reads them back
/// after batches of submissions; the regenerating schedule's decision pass writes the fill limit
/// and the tail bound.
pub const COUNTER_SCHEDULE: u64 = LAYOUT.counter_schedule;
/// Offsets from [`COUNTER_SCHEDULE`].
pub mod schedule_word {
    pub const NEXT_SAMPLE: usize = 0;
    pub const EMPTY: usize = 3;
    pub const INDIRECT: usize = 4;
    pub const INTERSECTED: usize = 5;
    pub const IDLE: usize = 6;
    pub const FILL_LIMIT: usize = 7;
    pub const TAIL_BOUND: usize = 8;
    /// Indirect arguments queue_setup clamped to the adapter's limit (wavefront/shared/indirect_args.wgsl).
    pub const CLAMPED: usize = 10;
    /// `--compact-states on`: states moved, and compactions run (summed over a share).
    pub const STATES_MOVED: usize = 11;
    pub const COMPACTIONS: usize = 12;
    /// The free slots at the last refill (the state compaction's own; the host never reads it).
    pub const COMPACT_FREE: usize = 13;
    /// Compactions whose free list and ray queue disagreed (nothing moved; a bug if > 0).
    pub const COMPACT_MISMATCH: usize = 14;
    /// (regenerate) The schedule's decision pass (`schedule_decide` in queue_setup.wgsl): the
    /// first chunk not yet in the film, the samples started at the last check, whether every
    /// chunk is in the film (the host stops recording once a read-back says so), the share's
    /// iterations up to then, iterations since the last check, whether the last check found every
    /// sample started, the tail passes run and the paths they finished, and whether every sample
    /// finished with chunks left out (a bug: the host refuses the render).
    pub const OLDEST: usize = 15;
    pub const STARTED_BEFORE: usize = 16;
    pub const DONE: usize = 17;
    pub const ITERATION: usize = 18;
    pub const SINCE_CHECK: usize = 19;
    pub const REFILL_DONE: usize = 20;
    pub const TAIL_PASSES: usize = 21;
    pub const TAIL_PATHS: usize = 22;
    /// Written by the host at a share's start: `--sync-every`, whether the render has the tail,
    /// and the most live paths at which it runs (`--tail-threshold` × pool, rounded down).
    pub const SYNC_EVERY: usize = 23;
    pub const TAIL_ON: usize = 24;
    pub const TAIL_MAX_LIVE: usize = 25;
    pub const FAILED: usize = 26;
    /// (`--refill in-place`) Tickets taken by refills in place since they were last settled
    /// (the GPU's own), then the slots refilled so by intersect and by shade (summed over a
    /// share).
    pub const CLAIMS: usize = 27;
    pub const REFILLED_INTERSECT: usize = 28;
    pub const REFILLED_SHADE: usize = 29;
    pub const WORDS: u64 = 30;
}
/// `COUNTER_RING_0`: the finished samples of each chunk of the sample ring.
pub const COUNTER_RING: u64 = LAYOUT.counter_ring;
pub const ARGS_COMPACT: u64 = LAYOUT.args_compact;
pub const ARGS_SHADOW: u64 = ARGS_COMPACT + 1;
pub const ARGS_REGENERATE: u64 = ARGS_COMPACT + 2;
pub const ARGS_TAIL: u64 = ARGS_COMPACT + 3;
pub const ARGS_COMPACT_STATES_FIND: u64 = ARGS_COMPACT + 4;
pub const ARGS_COMPACT_STATES_MOVE: u64 = ARGS_COMPACT + 5;
/// (regenerate) `accumulate_range`, sized by the decision pass.
pub const ARGS_ACCUMULATE: u64 = ARGS_COMPACT + 6;
/// `--shade per-texture`: each pattern's shade pass.
pub const ARGS_PATTERN_0: u64 = LAYOUT.args_pattern_0;
/// Which per-slot buffers a render's pool holds beyond the path itself: a buffer no pass of
/// the render reads is bound as one 16-byte element, so memory follows the scene and the knobs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PoolLayout {
    /// The queue each slot or position asks for next (`next_queue`): read by the scan
    /// compaction and by slot order's sweep.
    pub targets: bool,
    /// The scan compaction's offset and slot per position (`--compaction-method scan`, and the
    /// slot-depth key's scan).
    pub scan: bool,
    /// The pending shadow ray and its weight (`--nee on` in a scene with lights).
    pub shadow: bool,
    /// Regenerating (`--schedule regenerate`): the samples of its sample ring, whose radiance
    /// waits in `samples` for the accumulate pass; each slot also holds its sample and bounce.
    pub ring_samples: Option<u64>,
    /// A queue per costly pattern besides the others (`--shade per-texture`).
    pub pattern_queues: bool,
}

impl PoolLayout {
    /// Queue regions in the queues buffer (each a pool of 4-byte entries).
    pub const fn queue_regions(self) -> u64 {
        QUEUE_COUNT + if self.pattern_queues { PATTERN_QUEUES } else { 0 }
    }

    /// Bytes of GPU memory per pool slot: origin, direction, throughput and radiance (16 each)
    /// and an entry per queue region (4 each) always; the shadow ray and weight (16 each), the queue
    /// target (4), the scan's two words (4 each) and the slot's sample and bounce (8) where used.
    pub const fn bytes_per_path(self) -> u64 {
        4 * 16
            + self.queue_regions() * 4
            + if self.shadow { 2 * 16 } else { 0 }
            + if self.targets { 4 } else { 0 }
            + if self.scan { 2 * 4 } else { 0 }
            + if self.ring_samples.is_some() { 8 } else { 0 }
    }
}
/// Bytes of the largest single binding per slot (the queues), which bounds the pool.
pub const LARGEST_BINDING_PER_PATH: u64 = QUEUE_COUNT * 4;
pub const SCAN_WG: u64 = 256;

/// `block_sums` entries for a pool (shaders/wavefront/compact.wgsl): a total per scan block, then
/// each block's prefix sum (a separate copy, as the block pass's workgroups read other groups'
/// totals while writing their own prefixes).
pub fn scan_block_sums(pool: u64) -> u64 {
    2 * pool.div_ceil(SCAN_WG)
}

/// Workgroups of the scan's block pass: one per GROUP_CHUNKS × SCAN_WG blocks of SCAN_WG
/// positions (`GROUP_CHUNKS` in shaders/wavefront/compact.wgsl).
pub fn scan_block_groups(pool: u64) -> u64 {
    const GROUP_CHUNKS: u64 = 4;
    pool.div_ceil(GROUP_CHUNKS * SCAN_WG * SCAN_WG)
}

pub struct PathState {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    /// The indirect arguments in a group of their own, bound only by queue_setup: a buffer
    /// bound as storage cannot feed an indirect dispatch in the same pass.
    pub indirect_layout: wgpu::BindGroupLayout,
    pub indirect_group: wgpu::BindGroup,
    /// Per-slot radiance: the accumulate pass's input in waves.
    pub radiance: wgpu::Buffer,
    /// The sample ring (per-sample radiance): the accumulate pass's input when regenerating.
    pub samples: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    pub indirect: wgpu::Buffer,
    pub stats_bounces: u32,
    /// Slots in the pool.
    pub pool: u32,
}

/// The path-state bind group: the dispatch and wave uniforms (bindings 0 and 1), then the
/// storage buffers in binding order from 2 (`shaders/wavefront/shared/path_state.wgsl`).
fn bind_path_state(
    ctx: &GpuContext,
    params: &DispatchUniforms,
    wave: &wgpu::Buffer,
    storage: &[&wgpu::Buffer],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let mut entries = vec![uniform_entry(0, true), uniform_entry(1, false)];
    entries.extend((2..storage.len() as u32 + 2).map(|b| storage_entry(b, false)));
    let layout = ctx.bind_group_layout("path state", &entries);
    let mut bind = vec![
        wgpu::BindGroupEntry { binding: 0, resource: params.binding() },
        wgpu::BindGroupEntry { binding: 1, resource: wave.as_entire_binding() },
    ];
    bind.extend(
        storage
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32 + 2, resource: b.as_entire_binding() }),
    );
    let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("path state"),
        layout: &layout,
        entries: &bind,
    });
    (layout, bind_group)
}

impl PathState {
    pub fn new(
        ctx: &GpuContext,
        pool: u32,
        wave: WaveUniform,
        params: &DispatchUniforms,
        stats_bounces: u32,
        uses: PoolLayout,
        memory: &mut MemoryLedger,
    ) -> Result<Self> {
        let pool64 = pool as u64;
        let none = wgpu::BufferUsages::empty();
        check_size(ctx, "path queues", pool64 * uses.queue_regions() * 4)?;
        let mut buffer = |category, label, size, extra| -> Result<wgpu::Buffer> {
            Ok(memory.track(category, storage_zeroed(ctx, label, size, extra)?))
        };
        let origin = buffer(Mem::PathState, "path origin", pool64 * 16, none)?;
        let dir = buffer(Mem::PathState, "path direction", pool64 * 16, none)?;
        let throughput = buffer(Mem::PathState, "path throughput", pool64 * 16, none)?;
        let radiance = buffer(Mem::PathState, "path radiance", pool64 * 16, none)?;
        let queues = buffer(Mem::Queues, "path queues", pool64 * uses.queue_regions() * 4, none)?;
        assert!(stats_bounces as u64 <= MAX_STATS_BOUNCES);
        let counters = buffer(
            Mem::Counters,
            "queue counters",
            LAYOUT.counter_words * 4,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        )?;
        let indirect =
            buffer(Mem::Queues, "indirect args", LAYOUT.args_slots * 12, wgpu::BufferUsages::INDIRECT)?;
        // Per slot where used, else one element (no pass of this render reads it).
        let per_slot = |used: bool, bytes: u64| if used { pool64 * bytes } else { 16 };
        let next_queue = buffer(Mem::Queues, "queue targets", per_slot(uses.targets, 4), none)?;
        let scan_offset = buffer(Mem::Queues, "scan offsets", per_slot(uses.scan, 4), none)?;
        let block_sums = buffer(
            Mem::Queues,
            "scan block sums",
            if uses.scan { scan_block_sums(pool64) * 16 } else { 16 },
            none,
        )?;
        let scan_slot = buffer(Mem::Queues, "scan slots", per_slot(uses.scan, 4), none)?;
        let shadow_ray = buffer(Mem::ShadowQueue, "shadow ray", per_slot(uses.shadow, 16), none)?;
        let shadow_weight = buffer(Mem::ShadowQueue, "shadow weight", per_slot(uses.shadow, 16), none)?;
        // Regenerating: each slot's sample and bounce, and the chunk's finished samples. In
        // waves neither is read (slot = sample, bounce = iteration): minimal buffers.
        let path_sample =
            buffer(Mem::PathState, "path samples", per_slot(uses.ring_samples.is_some(), 8), none)?;
        let samples = buffer(Mem::Samples, "sample ring", uses.ring_samples.map_or(16, |c| c * 16), none)?;
        let wave_buf = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("wave"),
            contents: bytemuck::bytes_of(&wave),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        memory.add(Mem::Parameters, wave_buf.size());
        let storage = [
            &origin,
            &dir,
            &throughput,
            &radiance,
            &queues,
            &counters,
            &next_queue,
            &scan_offset,
            &block_sums,
            &scan_slot,
            &shadow_ray,
            &shadow_weight,
            &path_sample,
            &samples,
        ];
        let (layout, bind_group) = bind_path_state(ctx, params, &wave_buf, &storage);
        let indirect_layout = ctx.bind_group_layout("indirect args", &[storage_entry(0, false)]);
        let indirect_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("indirect args"),
            layout: &indirect_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: indirect.as_entire_binding() }],
        });
        ctx.check()?;
        Ok(Self {
            layout,
            bind_group,
            indirect_layout,
            indirect_group,
            radiance,
            samples,
            counters,
            indirect,
            stats_bounces,
            pool,
        })
    }

    /// Writes scheduling word `word` (`schedule_word`); it takes effect at the next submission.
    pub fn write_schedule_word(&self, ctx: &GpuContext, word: usize, value: u32) {
        ctx.queue.write_buffer(
            &self.counters,
            (COUNTER_SCHEDULE + word as u64) * 4,
            bytemuck::bytes_of(&value),
        );
    }

    /// Records the zeroing of the finished counts of the sample ring's chunks `chunks` (indices
    /// in the ring), once they are in the film and before a refill reuses them.
    pub fn clear_ring_counters(&self, enc: &mut wgpu::CommandEncoder, chunks: impl Iterator<Item = u32>) {
        for c in chunks {
            enc.clear_buffer(&self.counters, (COUNTER_RING + c as u64) * 4, Some(4));
        }
    }
}
