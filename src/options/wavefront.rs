//! The wavefront's options (`gpu/wavefront/`): how it keeps queues, shades, schedules its
//! paths and refills its pool. Each enum is spelled once, by its clap `ValueEnum` derive (serde's
//! kebab-case spelling is checked against it in `knobs.rs`'s tests); the mechanisms they choose
//! are described where they are built (`gpu/wavefront/<noun>.rs`).

use super::{RunSchedule, Schedule};

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

/// How the scan compaction scans a workgroup (`--scan`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scan {
    /// Subgroup operations where the adapter has them, else the workgroup scan.
    #[default]
    Auto,
    /// subgroupInclusiveAdd per subgroup, then the subgroup totals (3 barriers).
    Subgroup,
    /// Hillis–Steele over the workgroup in shared memory (16 barriers; no subgroups needed).
    Workgroup,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Append {
    /// Subgroup-aggregated where the adapter has subgroup operations, else per lane.
    #[default]
    Auto,
    /// One atomic per appending lane.
    Lane,
    /// One atomic per subgroup and queue, made by the first of the lanes appending to it.
    Subgroup,
}

/// Whether regenerated paths end with a megakernel pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tail {
    /// Iterate the passes until the last path ends.
    Off,
    /// Once the live paths are fewer than `tail_threshold` × pool, finish them in one pass.
    Megakernel,
}

/// Default `--tail-threshold`: the live fraction of the pool below which the tail takes over.
pub const DEFAULT_THRESHOLD: f64 = 0.05;

/// Default `--refill-below`: refill at every iteration, whatever is live.
pub const DEFAULT_REFILL_BELOW: f64 = 1.0;

/// Whether live path states are compacted below the live count before each refill.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CompactStates {
    /// Refills take the free slots wherever they are.
    Off,
    /// Before each refill, move the live paths above the live count into the free slots below
    /// it, so the refill's consecutive samples take one contiguous run of slots.
    On,
}

/// The key the ray queue is sorted by before each intersect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RaySort {
    /// The queue keeps the order its producing passes gave it (`--queue-order`).
    #[default]
    Off,
    /// By the ray direction's octant (8 keys).
    Octant,
    /// By octant, then the ray origin's cell of a 4×4×4 grid over the scene's bounds (512 keys).
    OctantCell,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QueueOrder {
    /// Slot order when regenerating with queues a job of at least four pools,
    /// arrival order otherwise: what measured faster (experiments/queue_order.json): the
    /// pool-wide scan pays where many refills scatter the pool, and only costs where waves empty
    /// it or a job barely refills it.
    #[default]
    Auto,
    /// As the producing pass met the paths (the scan keeps the previous queue's order).
    Arrival,
    /// By slot: the ray queue built by a pass over the pool's slots (needs queues): the scan
    /// method's stable scan, or the atomic method's sweep (runs of ascending slots).
    Slot,
    /// By slot, keyed by depth: the same scan lists the paths about to trace their first bounce
    /// after the camera ray (the last refill's children: consecutive samples) in one run after
    /// the others, as a wave would, rather than interleaved with paths at every depth.
    SlotDepth,
}

/// `auto` takes slot order for regenerating jobs of at least this many pools of samples. On
/// llvmpipe (experiments/results/llvmpipe-2core/queue_order) slot order lost at 1.4 pools
/// (400x225x16) and won at 12.4 (1200x675x16) on every scene with atomic appends; 4 lies
/// between, not measured itself.
pub const AUTO_SLOT_POOLS: u64 = 4;

/// How the wavefront groups its dispatches into compute passes (`--compute-passes`, issue 42).
/// In wgpu-core each compute pass becomes a command buffer of resource transitions spliced in
/// front of it, so a pass per dispatch pays that for each of a frame's thousands of dispatches;
/// `shared` (the default) lets consecutive dispatches share one pass until a copy or a
/// submission ends it. Set by measurement: on the NVIDIA H200 (release build of 50dcaad,
/// `experiments/results/nvidia-h200/compute_passes/`) sharing cut waves' rtiow-final
/// 1920x1080x64 frame from 1.23 s to 0.64 s and regenerate + tail's from 0.292 s to 0.243 s; on
/// llvmpipe the two are within noise. Barriers between dependent dispatches stay (wgpu orders each
/// dispatch's storage use within a pass too), so the film is the same. Per-pass timestamps need
/// a pass per dispatch: with `--timing passes` every dispatch keeps its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ComputePasses {
    /// One compute pass per dispatch.
    PerDispatch,
    /// Consecutive dispatches in one compute pass, up to the next copy or submission (where
    /// there are no per-pass timestamps).
    #[default]
    Shared,
}

/// Iterations between checks (and per submitted batch) when regenerating: each check's passes
/// and each batch's submission and read-back cost fixed time; each iteration recorded after the
/// work ran out costs its (empty) dispatches.
pub const DEFAULT_SYNC_EVERY: u32 = 8;

/// Most iterations between read-backs.
pub const MAX_SYNC_EVERY: u32 = 1024;

/// Default `--chunk-pools`: the sample ring holds at most this many chunks of one pool of
/// samples each. Its per-sample radiance (16 bytes a sample) costs this many times the pool's
/// radiance; refills stop when it is full and its oldest chunk has paths still going.
pub const CHUNK_POOLS: u32 = 8;

/// Most chunks the sample ring may hold (`MAX_RING_CHUNKS` counters).
pub const MAX_CHUNK_POOLS: u32 = 1024;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WavefrontOptions {
    /// Paths in flight; `None`: the default from the adapter's limits.
    pub pool_size: Option<u32>,
    pub workgroup_size: u32,
    pub compaction: Compaction,
    pub shade: ShadePasses,
    pub schedule: Schedule,
    /// Regenerating: iterations between the GPU's checks of the schedule's counters, and per
    /// batch the host submits (more: fewer submissions and read-backs, up to this many idle
    /// iterations at the image's end and more speculative ones; with the tail, the check runs
    /// every iteration once every sample has started).
    pub sync_every: u32,
    /// Regenerating: batches the host keeps submitted before it waits for the oldest one's
    /// read-back (`--batches-in-flight`): 1 waits for each check, the GPU idle while the host
    /// reads and records (the loop before issue 42); more keep newer batches queued meanwhile.
    pub batches_in_flight: u32,
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
            sync_every: DEFAULT_SYNC_EVERY,
            batches_in_flight: BATCHES_IN_FLIGHT,
            tail: Tail::Off,
            tail_threshold: DEFAULT_THRESHOLD,
            chunk_pools: CHUNK_POOLS,
            scan: Scan::Auto,
            append: Append::Auto,
            compute_passes: ComputePasses::Shared,
            queue_order: QueueOrder::Auto,
            refill_below: DEFAULT_REFILL_BELOW,
            compact_states: CompactStates::Off,
            ray_sort: RaySort::Off,
        }
    }
}

impl WavefrontOptions {
    /// `--schedule auto` made concrete ([`Schedule::Auto`]): `regenerate` with the megakernel
    /// tail on a GPU, `waves` on a software adapter. Other schedules stay as given.
    pub fn resolve(mut self, software: bool) -> ResolvedWavefront {
        let schedule = match self.schedule {
            Schedule::Auto if software => RunSchedule::Waves,
            Schedule::Auto => {
                self.tail = Tail::Megakernel;
                RunSchedule::Regenerate
            }
            Schedule::Waves => RunSchedule::Waves,
            Schedule::Regenerate => RunSchedule::Regenerate,
        };
        self.schedule = schedule.into();
        ResolvedWavefront { options: self, schedule }
    }
}

/// The wavefront's options with the schedule resolved: what runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedWavefront {
    /// The options, `schedule` concrete (what reports record).
    pub options: WavefrontOptions,
    pub schedule: RunSchedule,
}

/// Default `--batches-in-flight`: batches of `--sync-every` iterations the regenerating host
/// loop keeps in flight (each with its own staging buffer for the counters' read-back): enough
/// that waiting for the oldest leaves newer ones queued, so the GPU never idles for the host
/// inside a share.
pub const BATCHES_IN_FLIGHT: u32 = 3;

/// Most `--batches-in-flight`.
pub const MAX_BATCHES_IN_FLIGHT: u32 = 16;

impl QueueOrder {
    /// The order a render uses, `Arrival` or `Slot`, with this schedule and compaction, for a
    /// job of `samples` samples on a pool of `pool` slots.
    pub fn resolve(self, schedule: Schedule, compaction: Compaction, samples: u64, pool: u32) -> QueueOrder {
        match self {
            QueueOrder::Auto
                if schedule == Schedule::Regenerate
                    && compaction != Compaction::Off
                    && samples >= AUTO_SLOT_POOLS * pool as u64 =>
            {
                QueueOrder::Slot
            }
            QueueOrder::Auto => QueueOrder::Arrival,
            order => order,
        }
    }

    /// Whether the ray queue is built by a pass over the pool's slots (either key).
    pub fn is_slot(self) -> bool {
        matches!(self, QueueOrder::Slot | QueueOrder::SlotDepth)
    }
}
