//! The GPU methods on wgpu, and the plumbing they share.

pub mod accumulate;
pub mod binding;
pub mod buffers;
pub mod context;
pub mod dispatch_plan;
pub mod gpu_render;
pub mod headless;
pub mod instrument;
pub mod loop_limit;
pub mod megakernel;
pub mod memory;
pub mod pipeline_limits;
pub mod preheat;
pub mod scene_buffers;
pub mod scene_split;
pub mod shader_checks;
pub mod shader_variants;
pub mod shaders;
pub mod specialize;
pub mod stage;
pub mod stage_cache;
pub mod state;
pub mod timestamp_pair;
pub mod timing;
pub mod wavefront;

/// One static label per GPU pass: the same string names the pipeline, the WGSL entry point,
/// the timestamp slot, the row of the timing table and the key in JSON reports.
pub mod label {
    pub const MEGAKERNEL: &str = "megakernel";
    /// `--method megakernel --schedule regenerate`: persistent threads that regenerate paths.
    pub const MEGAKERNEL_REGENERATE: &str = "megakernel_regenerate";
    pub const ACCUMULATE: &str = "accumulate";
    /// `--schedule regenerate` (wavefront): adds the finished chunks of the sample ring.
    pub const ACCUMULATE_RANGE: &str = "accumulate_range";
    pub const GENERATE: &str = "generate";
    /// `--schedule regenerate`: empties the pool at a share's start.
    pub const REGENERATE_INIT: &str = "regenerate_init";
    /// `--schedule regenerate`: sizes the refill from the free slots and the samples left.
    pub const QUEUE_SETUP_REGENERATE: &str = "queue_setup_regenerate";
    /// `--compact-states on`: lists the live paths above the live count and the free slots below.
    pub const COMPACT_STATES_FIND: &str = "compact_states_find";
    /// `--compact-states on`: sizes the move pass.
    pub const QUEUE_SETUP_COMPACT_STATES: &str = "queue_setup_compact_states";
    /// `--compact-states on`: moves those paths into those slots before the refill.
    pub const COMPACT_STATES_MOVE: &str = "compact_states_move";
    /// `--schedule regenerate`: starts new samples in the slots whose paths ended.
    pub const REGENERATE: &str = "regenerate";
    pub const QUEUE_SETUP_INTERSECT: &str = "queue_setup_intersect";
    /// `--ray-sort`: counts the ray queue's entries per key (direction octant, origin cell).
    pub const RAY_SORT_COUNT: &str = "ray_sort_count";
    /// `--ray-sort`: each key's first position in the sorted queue (one workgroup).
    pub const RAY_SORT_SCAN: &str = "ray_sort_scan";
    /// `--ray-sort`: writes the ray queue back in key order.
    pub const RAY_SORT_SCATTER: &str = "ray_sort_scatter";
    pub const INTERSECT: &str = "intersect";
    /// `wavetrace intersect-cost`: intersect's traversal of camera rays made in place, with no
    /// path state read or written (a diagnostic).
    pub const INTERSECT_REGISTERS: &str = "intersect_registers";
    pub const QUEUE_SETUP_SHADE: &str = "queue_setup_shade";
    /// Shade passes by material kind (`layout::material_kind` order).
    pub const SHADE_BY_KIND: [&str; crate::layout::material_kind::COUNT] =
        ["shade_lambertian", "shade_metal", "shade_dielectric", "shade_emissive"];
    /// `--shade per-texture`: the shade passes of the costly patterns (`scene::Pattern::ALL`
    /// order).
    pub const SHADE_BY_PATTERN: [&str; 8] = [
        "shade_noise",
        "shade_marble",
        "shade_wood",
        "shade_ridged",
        "shade_warp",
        "shade_cellular",
        "shade_crackle",
        "shade_value",
    ];
    /// The single shade pass with a material switch.
    pub const SHADE: &str = "shade";
    /// `--shade sorted`: one shade pass over the material queues end to end.
    pub const SHADE_SORTED: &str = "shade_sorted";
    pub const COMPACT_SCAN: &str = "compact_scan";
    pub const COMPACT_BLOCKS: &str = "compact_blocks";
    pub const COMPACT_SCATTER: &str = "compact_scatter";
    /// Slot order with atomic appends: lists every slot on the next ray queue, the free list or
    /// the shadow queue.
    pub const SLOT_SWEEP: &str = "slot_sweep";
    pub const QUEUE_SETUP_SHADOW: &str = "queue_setup_shadow";
    /// Shadow rays of next-event estimation (`--nee on`).
    pub const SHADOW: &str = "shadow";
    /// `--schedule regenerate`: the host's check on the GPU after an iteration: which chunks go
    /// into the film, the refill limit, whether the tail runs (and its size), the share done.
    pub const SCHEDULE_DECIDE: &str = "schedule_decide";
    /// `--schedule regenerate --nee on`: queue_setup_shadow and schedule_decide in one dispatch,
    /// on the iterations that have both.
    pub const QUEUE_SETUP_SHADOW_DECIDE: &str = "queue_setup_shadow_decide";
    /// `--tail megakernel`: finishes paths megakernel-style: a share's last ones, and the oldest
    /// chunks' last ones when the sample ring needs them back.
    pub const TAIL: &str = "tail";
    /// `wavetrace dispatch-cost`: one link of a chain of dependent tiny dispatches.
    pub const CHAIN_LINK: &str = "chain_link";
    /// `wavetrace dispatch-cost`: a tiny dispatch that only reads (no barrier between them).
    pub const CHAIN_READ: &str = "chain_read";
    /// `wavetrace bandwidth`: each thread copies one 16-byte element.
    pub const STREAM_COPY: &str = "stream_copy";
    /// `wavetrace bandwidth`: each thread reads one 16-byte element.
    pub const STREAM_READ: &str = "stream_read";
    /// `wavetrace bandwidth`: `copy_buffer_to_buffer` between two timestamped passes.
    pub const BUFFER_COPY: &str = "buffer_copy";
    /// Busy work just before a timed frame, so the GPU's clocks are up (`preheat_seconds`).
    pub const PREHEAT: &str = "preheat";

    /// What a pass does, for the results pages' sums of pass time.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Group {
        Intersect,
        Shade,
        Shadow,
        /// Queues built: the scan compaction's passes, slot order's sweep, the ray sort.
        Compaction,
        /// Paths started: generate, regenerate (with the state compaction before refills).
        Generate,
        Tail,
        /// Queue set-up, the schedule's decision, accumulation and the rest.
        Other,
    }

    /// The group of the pass labelled `label`.
    pub fn group(label: &str) -> Group {
        match label {
            INTERSECT => Group::Intersect,
            SHADE | SHADE_SORTED => Group::Shade,
            l if SHADE_BY_KIND.contains(&l) || SHADE_BY_PATTERN.contains(&l) => Group::Shade,
            SHADOW => Group::Shadow,
            COMPACT_SCAN | COMPACT_BLOCKS | COMPACT_SCATTER | SLOT_SWEEP | RAY_SORT_COUNT | RAY_SORT_SCAN
            | RAY_SORT_SCATTER => Group::Compaction,
            // The ray sort's passes in reports committed before it took one name.
            "sort_rays_count" | "sort_rays_scan" | "sort_rays_scatter" => Group::Compaction,
            GENERATE | REGENERATE | REGENERATE_INIT | COMPACT_STATES_FIND | COMPACT_STATES_MOVE => {
                Group::Generate
            }
            TAIL => Group::Tail,
            _ => Group::Other,
        }
    }
}

pub use context::GpuContext;
pub use gpu_render::GpuRender;
