//! The wavefront's options (`gpu/wavefront/`): how it keeps queues, shades, schedules its
//! paths and refills its pool. Each enum is spelled once, by its clap `ValueEnum` derive (serde's
//! kebab-case spelling is checked against it in `knobs.rs`'s tests); the mechanisms they choose
//! are described where they are built (`gpu/wavefront/<noun>.rs`).

use super::{PoolSize, RunSchedule, Schedule};

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
    /// As per-material, and a pass of its own for each costly procedural pattern (noise,
    /// marble, ...) the scene's diffuse and metal materials use, so that each pattern is shaded
    /// coherently (needs atomic queues).
    PerTexture,
    /// One pass over every hit with a material switch (the megakernel's divergence).
    Single,
    /// One pass over the material queues laid end to end, so hits come sorted by material kind:
    /// a subgroup's lanes share a kind but at the queues' seams (Cycles' way: one shade kernel
    /// over paths sorted by shader), one dispatch where per-material takes one per kind, every
    /// kind compiled in (needs queues).
    Sorted,
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
    /// arrival order otherwise: what measured faster (docs/methods.md): the pool-wide scan pays
    /// where many refills scatter the pool, and only costs where waves empty it or a job barely
    /// refills it.
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

/// How the passes that consume a queue (intersect, shade, shadow, the refill) are launched
/// (`--launch`, issue 42).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Launch {
    /// Sized on the GPU: a setup pass turns the queue's length into the pass's workgroup count,
    /// read by an indirect dispatch (vello's way).
    #[default]
    Indirect,
    /// At the pool's size (a wave's paths): threads past the queue's length return at once, as
    /// pbrt-v4's `ForAllQueued` launches its queues' largest size; no indirect arguments read.
    Pool,
}

/// Where the regenerating wavefront starts its next samples (`--refill`, issue 44: generate fused
/// into the passes where paths end).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Refill {
    /// A pass at each iteration's start takes the slots on the free list (Laine et al.'s
    /// regeneration kernel).
    #[default]
    Pass,
    /// Where a path ends (an escape in intersect, an end in shade) its slot takes the share's
    /// next sample there and then and queues its camera ray: no free-list round trip; the pass
    /// takes only slots freed while the sample ring was full.
    InPlace,
}

/// Where the wavefront traces the shadow rays of next-event estimation (`--shadow-rays`, issue
/// 44).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowRays {
    /// Queued by shade with their weights and traced by the shadow pass (pbrt-v4's and Cycles'
    /// way): the ray and its weight stored and read back.
    #[default]
    Pass,
    /// Traced by shade where it samples the light, as the megakernel does: nothing stored but
    /// the radiance, no shadow pass, a traversal inside shade (needs queues).
    Inline,
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

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, clap::Args)]
#[command(next_help_heading = "Wavefront")]
pub struct WavefrontOptions {
    /// Wavefront: paths in flight (default about a million, less where the adapter's storage
    /// bindings are smaller; a pool that does not fit is reduced with a notice), or `device`:
    /// Cycles' rule, max(SMs × threads per SM, 65536) × 16 (about 4.3 million on an H100 or
    /// H200; the SM count from NVIDIA's NVML, the default pool where it is unknown).
    #[arg(long, value_parser = PoolSize::parse, hide_short_help = true)]
    pub pool_size: Option<PoolSize>,
    /// Threads per workgroup: `--workgroup-size`, which the command line sets for both GPU
    /// methods.
    #[arg(skip = DEFAULT_WORKGROUP_SIZE)]
    pub workgroup_size: u32,
    /// Queues kept dense, by atomic appends or a scan, or none (every pass over the whole
    /// pool): `--compaction on|off` and `--compaction-method` on the command line.
    #[arg(skip = Compaction::Atomic)]
    pub compaction: Compaction,
    /// Wavefront: one shade pass per material kind, one per material kind and costly pattern
    /// (`per-texture`: each pattern shaded in a pass of its own; needs atomic queues), one
    /// with a material switch (`single`), or one over the material queues end to end (`sorted`:
    /// subgroups of one kind, one dispatch; needs queues).
    #[arg(long, value_enum, default_value_t = ShadePasses::PerMaterial, hide_short_help = true)]
    pub shade: ShadePasses,
    /// `--schedule`, which the command line sets for both GPU methods.
    #[arg(skip = Schedule::Waves)]
    pub schedule: Schedule,
    /// Wavefront, regenerate: iterations between checks of the schedule's counters (on the GPU,
    /// which then adds complete chunks to the film; up to this many iterations idle at the
    /// image's end), and per batch the host submits and reads back without waiting. With --tail
    /// megakernel, the check runs after every iteration once every sample has started, so the
    /// tail starts when it is due.
    #[arg(long, default_value_t = DEFAULT_SYNC_EVERY, hide_short_help = true)]
    pub sync_every: u32,
    /// Wavefront, regenerate: batches of --sync-every iterations submitted before the host waits
    /// for the oldest one's read-back (1: it waits for each check, the GPU idle meanwhile, as
    /// before the GPU decided; more: newer batches keep the GPU busy while it waits).
    #[arg(long, default_value_t = BATCHES_IN_FLIGHT, hide_short_help = true)]
    pub batches_in_flight: u32,
    /// Wavefront, regenerate: finish paths in one megakernel-style pass: the image's last ones
    /// once at most --tail-threshold × pool are left, and the oldest chunks' last ones (each at
    /// most that many) when the sample ring would stop the refills.
    #[arg(long, value_enum, default_value_t = Tail::Off, hide_short_help = true)]
    pub tail: Tail,
    /// Wavefront, --tail megakernel: the live fraction of the pool, in (0, 1], below which the
    /// tail takes over.
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, hide_short_help = true)]
    pub tail_threshold: f64,
    /// Wavefront, --schedule regenerate: chunks of one pool of samples in the sample ring.
    /// Refills run at most this many chunks ahead of the oldest one not yet in the film (a
    /// larger ring waits less on its oldest chunk's longest paths); the ring takes 16 bytes a
    /// sample, within one storage binding.
    #[arg(long, default_value_t = CHUNK_POOLS, hide_short_help = true)]
    pub chunk_pools: u32,
    /// Wavefront, --compaction-method scan: scan workgroups with subgroup operations (where the
    /// adapter has them: `auto`) or with the Hillis–Steele workgroup scan.
    #[arg(long, value_enum, default_value_t = Scan::Auto, hide_short_help = true)]
    pub scan: Scan,
    /// Wavefront: append paths to queues with one atomic per subgroup and queue (where the
    /// adapter has subgroups: `auto`) or one per lane.
    #[arg(long, value_enum, default_value_t = Append::Auto, hide_short_help = true)]
    pub append: Append,
    /// Wavefront: one compute pass per dispatch, or consecutive dispatches sharing one (up to the
    /// next copy or submission; only where passes are not timed: with `--timing frame`).
    #[arg(long, value_enum, default_value_t = ComputePasses::Shared, hide_short_help = true)]
    pub compute_passes: ComputePasses,
    /// Wavefront: launch the passes that consume a queue (intersect, shade, shadow, the refill)
    /// with the workgroups a setup pass wrote from the queue's length (`indirect`), or at the
    /// pool's size, threads past the queue's length returning at once (`pool`, pbrt-v4's way).
    #[arg(long, value_enum, default_value_t = Launch::Indirect, hide_short_help = true)]
    pub launch: Launch,
    /// Wavefront, --nee on: trace the shadow rays in a pass of their own, queued with their
    /// weights (`pass`), or in shade where the light is sampled, storing nothing but the
    /// radiance (`inline`, the megakernel's way; needs queues).
    #[arg(long, value_enum, default_value_t = ShadowRays::Pass, hide_short_help = true)]
    pub shadow_rays: ShadowRays,
    /// Wavefront: keep queues in the order their paths arrived, or build the ray queue in slot
    /// order by a pass over the pool (a subgroup reads neighbouring path states; regenerated
    /// samples fill the lowest free slots): a stable scan with --compaction-method scan, a sweep
    /// of appends (runs of ascending slots) with atomic; optionally keyed by depth (`slot-depth`,
    /// always a scan: a refill's first bounces in one run, as in a wave); `auto`: slot order when
    /// regenerating a job of at least 4 pools of samples, arrival order otherwise.
    #[arg(long, value_enum, default_value_t = QueueOrder::Auto, hide_short_help = true)]
    pub queue_order: QueueOrder,
    /// Wavefront, --schedule regenerate: refill the pool only once at most this fraction of it,
    /// in (0, 1], is live (1: at every iteration, into whatever slots paths just left; less:
    /// larger batches of consecutive samples, as Cycles schedules new work only when too few
    /// paths are left).
    #[arg(long, default_value_t = DEFAULT_REFILL_BELOW, hide_short_help = true)]
    pub refill_below: f64,
    /// Wavefront, --schedule regenerate: start the next samples in a pass over the free slots
    /// (`pass`), or in the slot of each path that ends, in intersect or shade, as it ends
    /// (`in-place`: generate fused into them; needs --compaction-method atomic and refills at
    /// every iteration).
    #[arg(long, value_enum, default_value_t = Refill::Pass, hide_short_help = true)]
    pub refill: Refill,
    /// Wavefront, --schedule regenerate: before each refill, move the live paths above the live
    /// count into the free slots below it (Cycles' compact_states), so the refill's consecutive
    /// samples take one contiguous run of slots. Needs --compaction on.
    #[arg(long, value_enum, default_value_t = CompactStates::Off, hide_short_help = true)]
    pub compact_states: CompactStates,
    /// Wavefront: before each intersect, sort the ray queue by the ray direction's octant
    /// (`octant`), or by octant and the origin's cell of a 4x4x4 grid over the scene
    /// (`octant-cell`), so a subgroup's lanes traverse the same part of the BVH (a counting sort:
    /// three passes). Needs --compaction on.
    #[arg(long, value_enum, default_value_t = RaySort::Off, hide_short_help = true)]
    pub ray_sort: RaySort,
}

/// Threads per workgroup of both GPU methods unless `--workgroup-size` says otherwise.
pub const DEFAULT_WORKGROUP_SIZE: u32 = 64;

impl Default for WavefrontOptions {
    fn default() -> Self {
        Self {
            pool_size: None,
            workgroup_size: DEFAULT_WORKGROUP_SIZE,
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
            launch: Launch::Indirect,
            shadow_rays: ShadowRays::Pass,
            queue_order: QueueOrder::Auto,
            refill_below: DEFAULT_REFILL_BELOW,
            refill: Refill::Pass,
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
