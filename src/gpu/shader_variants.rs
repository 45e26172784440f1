//! The entry shaders and the variants of each: the one list `build.rs` composes and validates,
//! and from which it writes the constants `gpu::shaders` embeds, so no variant is composed that
//! nothing embeds and none is embedded unvalidated. Std only: `build.rs` includes this file.
//!
//! A variant swaps hooks: a strategy an entry takes from an included file (a no-op
//! instrumentation, per-lane atomics, a workgroup scan) is replaced by another file (subgroup
//! counters, subgroup-aggregated atomics, a subgroup scan), so every entry is written once.

/// A strategy an entry includes from a file that a variant replaces with another.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hook {
    /// `--instrument`: SIMD-efficiency counters for the no-op hooks, and the coherence counters
    /// where the entry includes them. Instrumented entry points carry markers for the subgroup
    /// width they hand the counters (shaders/shared/instrument.wgsl; build.rs fills them).
    Instrument,
    /// `--append subgroup`: queue appends aggregated per subgroup instead of one atomic per lane.
    AppendSubgroup,
    /// `--scan subgroup`: the compaction's workgroup scan by subgroup operations.
    ScanSubgroup,
    /// The regenerating megakernel on adapters with subgroups: the lanes that need samples take
    /// them with one atomic per subgroup.
    TakeSampleSubgroup,
}

impl Hook {
    /// (file an entry includes, the file the variant reads instead), under `shaders/`. The first
    /// pair's file is the hook's: an entry has the variant only if it includes that file.
    pub fn swaps(self) -> &'static [(&'static str, &'static str)] {
        match self {
            Hook::Instrument => &[
                ("shared/instrument.wgsl", "shared/instrument_on.wgsl"),
                ("wavefront/shared/coherence.wgsl", "wavefront/shared/coherence_on.wgsl"),
            ],
            Hook::AppendSubgroup => {
                &[("wavefront/shared/append.wgsl", "wavefront/shared/append_subgroup.wgsl")]
            }
            Hook::ScanSubgroup => &[("wavefront/shared/scan.wgsl", "wavefront/shared/scan_subgroup.wgsl")],
            Hook::TakeSampleSubgroup => {
                &[("megakernel/take_sample.wgsl", "megakernel/take_sample_subgroup.wgsl")]
            }
        }
    }

    /// What the variant adds to the composed file's name.
    pub fn suffix(self) -> &'static str {
        match self {
            Hook::Instrument => ".instrumented",
            Hook::AppendSubgroup => ".append_subgroup",
            Hook::ScanSubgroup => ".scan_subgroup",
            Hook::TakeSampleSubgroup => ".take_sample_subgroup",
        }
    }
}

/// An entry shader and the hooks it comes in variants of: one variant per subset of them.
pub struct Entry {
    /// Its constant in `gpu::shaders`.
    pub name: &'static str,
    /// Under `shaders/`.
    pub file: &'static str,
    pub hooks: &'static [Hook],
}

impl Entry {
    /// Every variant's hooks, the plain one (none) first: variant `i` has `hooks[k]` where bit `k`
    /// of `i` is set (the order `gpu::shaders::Shader` indexes by).
    pub fn variants(&self) -> Vec<Vec<Hook>> {
        (0..1usize << self.hooks.len())
            .map(|i| (0..self.hooks.len()).filter(|k| i >> k & 1 == 1).map(|k| self.hooks[k]).collect())
            .collect()
    }

    /// The composed file's name in `OUT_DIR`: the entry's path with `/` as `_`, then the suffixes.
    pub fn composed_name(&self, hooks: &[Hook]) -> String {
        let stem = self.file.trim_end_matches(".wgsl").replace('/', "_");
        let suffixes: String = hooks.iter().map(|h| h.suffix()).collect();
        format!("{stem}{suffixes}.wgsl")
    }
}

use Hook::*;

/// Every entry shader the binary embeds, with the hooks its callers choose between.
pub const ENTRIES: &[Entry] = &[
    Entry { name: "MEGAKERNEL", file: "megakernel.wgsl", hooks: &[Instrument] },
    Entry {
        name: "MEGAKERNEL_REGENERATE",
        file: "megakernel_regenerate.wgsl",
        hooks: &[Instrument, TakeSampleSubgroup],
    },
    Entry { name: "ACCUMULATE", file: "accumulate.wgsl", hooks: &[] },
    Entry { name: "DISPATCH_CHAIN", file: "dispatch_chain.wgsl", hooks: &[] },
    Entry { name: "BANDWIDTH", file: "bandwidth.wgsl", hooks: &[] },
    Entry { name: "PREHEAT", file: "preheat.wgsl", hooks: &[] },
    Entry { name: "RNG_PROBE", file: "tests/rng_probe.wgsl", hooks: &[] },
    Entry { name: "IMAGE_PROBE", file: "tests/image_probe.wgsl", hooks: &[] },
    Entry { name: "INDIRECT_PROBE", file: "tests/indirect_probe.wgsl", hooks: &[] },
    Entry { name: "SCHEDULE_PROBE", file: "tests/schedule_probe.wgsl", hooks: &[] },
    Entry { name: "GENERATE", file: "wavefront/generate.wgsl", hooks: &[Instrument, AppendSubgroup] },
    Entry { name: "INTERSECT", file: "wavefront/intersect.wgsl", hooks: &[Instrument, AppendSubgroup] },
    // `wavetrace intersect-cost`'s diagnostic twin of intersect (never instrumented).
    Entry { name: "INTERSECT_REGISTERS", file: "wavefront/intersect_registers.wgsl", hooks: &[] },
    Entry { name: "SHADE", file: "wavefront/shade.wgsl", hooks: &[Instrument, AppendSubgroup] },
    Entry { name: "SHADOW", file: "wavefront/shadow.wgsl", hooks: &[Instrument, AppendSubgroup] },
    Entry { name: "TAIL", file: "wavefront/tail.wgsl", hooks: &[Instrument, AppendSubgroup] },
    Entry { name: "QUEUE_SETUP", file: "wavefront/queue_setup.wgsl", hooks: &[] },
    Entry { name: "COMPACT_STATES", file: "wavefront/compact_states.wgsl", hooks: &[] },
    Entry { name: "RAY_SORT", file: "wavefront/ray_sort.wgsl", hooks: &[] },
    Entry { name: "COMPACT", file: "wavefront/compact.wgsl", hooks: &[ScanSubgroup] },
    Entry { name: "SLOT_SWEEP", file: "wavefront/slot_sweep.wgsl", hooks: &[AppendSubgroup] },
];
