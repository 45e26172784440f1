//! WGSL entry shaders, composed from `shaders/` and validated by `build.rs`.

pub const MEGAKERNEL: &str = include_str!(concat!(env!("OUT_DIR"), "/megakernel.wgsl"));
pub const ACCUMULATE: &str = include_str!(concat!(env!("OUT_DIR"), "/accumulate.wgsl"));
pub const RNG_PROBE: &str = include_str!(concat!(env!("OUT_DIR"), "/tests_rng_probe.wgsl"));
