//! WGSL entry shaders, composed from `shaders/` and validated by `build.rs`. Shaders with the
//! instrumentation hook also come in an `--instrument` variant.

macro_rules! composed {
    ($name:literal) => {
        include_str!(concat!(env!("OUT_DIR"), "/", $name, ".wgsl"))
    };
}

/// A shader in its timing and `--instrument` variants.
pub struct Variants {
    pub plain: &'static str,
    pub instrumented: &'static str,
}

impl Variants {
    pub fn get(&self, instrumented: bool) -> &'static str {
        if instrumented {
            self.instrumented
        } else {
            self.plain
        }
    }
}

macro_rules! variants {
    ($name:literal) => {
        Variants {
            plain: composed!($name),
            instrumented: include_str!(concat!(env!("OUT_DIR"), "/", $name, ".instrumented.wgsl")),
        }
    };
}

pub const MEGAKERNEL: Variants = variants!("megakernel");
pub const MEGAKERNEL_REGENERATE: Variants = variants!("megakernel_regenerate");
pub const MEGAKERNEL_REGENERATE_SUBGROUP: Variants = variants!("megakernel_regenerate_subgroup");
pub const ACCUMULATE: &str = composed!("accumulate");
pub const RNG_PROBE: &str = composed!("tests_rng_probe");
pub const INDIRECT_PROBE: &str = composed!("tests_indirect_probe");
pub const GENERATE: Variants = variants!("wavefront_generate");
pub const INTERSECT: Variants = variants!("wavefront_intersect");
pub const SHADE: Variants = variants!("wavefront_shade");
pub const SHADOW: Variants = variants!("wavefront_shadow");
pub const TAIL: Variants = variants!("wavefront_tail");
pub const QUEUE_SETUP: &str = composed!("wavefront_queue_setup");
pub const COMPACT: &str = composed!("wavefront_compact");
pub const COMPACT_SUBGROUP: &str = composed!("wavefront_compact_subgroup");
