//! WGSL entry shaders, composed from `shaders/` and validated by `build.rs`. Shaders with the
//! instrumentation hook also come in an `--instrument` variant.

macro_rules! composed {
    ($name:literal) => {
        include_str!(concat!(env!("OUT_DIR"), "/", $name, ".wgsl"))
    };
}

/// A shader in its timing and `--instrument` variants, and for wavefront passes that append to
/// queues, both again with subgroup-aggregated appends (`--append subgroup`).
pub struct Variants {
    pub plain: &'static str,
    pub instrumented: &'static str,
    /// (plain, instrumented) with `shared/append_subgroup.wgsl`.
    pub subgroup_append: Option<(&'static str, &'static str)>,
}

impl Variants {
    pub fn get(&self, instrumented: bool) -> &'static str {
        self.select(instrumented, false)
    }

    /// The variant with subgroup-aggregated appends where asked for (passes that append
    /// nothing have one variant for both).
    pub fn select(&self, instrumented: bool, subgroup_append: bool) -> &'static str {
        match (self.subgroup_append, instrumented) {
            (Some((plain, _)), false) if subgroup_append => plain,
            (Some((_, instrumented)), true) if subgroup_append => instrumented,
            (_, true) => self.instrumented,
            (_, false) => self.plain,
        }
    }
}

macro_rules! variants {
    ($name:literal) => {
        Variants {
            plain: composed!($name),
            instrumented: include_str!(concat!(env!("OUT_DIR"), "/", $name, ".instrumented.wgsl")),
            subgroup_append: None,
        }
    };
    ($name:literal, appends) => {
        Variants {
            plain: composed!($name),
            instrumented: include_str!(concat!(env!("OUT_DIR"), "/", $name, ".instrumented.wgsl")),
            subgroup_append: Some((
                include_str!(concat!(env!("OUT_DIR"), "/", $name, ".subgroup.wgsl")),
                include_str!(concat!(env!("OUT_DIR"), "/", $name, ".instrumented.subgroup.wgsl")),
            )),
        }
    };
}

pub const MEGAKERNEL: Variants = variants!("megakernel");
pub const MEGAKERNEL_REGENERATE: Variants = variants!("megakernel_regenerate");
pub const MEGAKERNEL_REGENERATE_SUBGROUP: Variants = variants!("megakernel_regenerate_subgroup");
pub const ACCUMULATE: &str = composed!("accumulate");
pub const DISPATCH_CHAIN: &str = composed!("dispatch_chain");
pub const BANDWIDTH: &str = composed!("bandwidth");
pub const PREHEAT: &str = composed!("preheat");
pub const RNG_PROBE: &str = composed!("tests_rng_probe");
pub const INDIRECT_PROBE: &str = composed!("tests_indirect_probe");
pub const SCHEDULE_PROBE: &str = composed!("tests_schedule_probe");
pub const GENERATE: Variants = variants!("wavefront_generate", appends);
pub const INTERSECT: Variants = variants!("wavefront_intersect", appends);
/// `wavetrace intersect-cost`'s diagnostic twin of intersect (never instrumented).
pub const INTERSECT_REGISTERS: &str = composed!("wavefront_intersect_registers");
pub const SHADE: Variants = variants!("wavefront_shade", appends);
pub const SHADOW: Variants = variants!("wavefront_shadow", appends);
pub const TAIL: Variants = variants!("wavefront_tail", appends);
pub const QUEUE_SETUP: &str = composed!("wavefront_queue_setup");
pub const COMPACT_STATES: &str = composed!("wavefront_compact_states");
pub const SORT_RAYS: &str = composed!("wavefront_sort_rays");
pub const COMPACT: &str = composed!("wavefront_compact");
/// Slot order's sweep: [per-lane appends, subgroup-aggregated appends] (never instrumented).
pub const SLOT_SWEEP: [&str; 2] = [
    composed!("wavefront_slot_sweep"),
    include_str!(concat!(env!("OUT_DIR"), "/wavefront_slot_sweep.subgroup.wgsl")),
];
pub const COMPACT_SUBGROUP: &str = composed!("wavefront_compact_subgroup");
