//! `--shade`: how the wavefront dispatches shading (`gpu/wavefront/shade.rs` builds its passes).

use super::*;

/// How shading is dispatched.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadePasses {
    /// One pass per material kind the scene uses.
    #[default]
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
enum_values!(ShadePasses);

flag! {
    /// Wavefront: one shade pass per material kind, one per material kind and costly pattern
    /// (`per-texture`: each pattern shaded in a pass of its own; needs atomic queues), one
    /// with a material switch (`single`), or one over the material queues end to end (`sorted`:
    /// subgroups of one kind, one dispatch; needs queues).
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    shade: ShadePasses
}

pub const KNOB: Knob = knob!("shade", "shade", WAVEFRONT, ShadePasses, o => o.wavefront.shade);

pub const PER_TEXTURE: Rule = Rule {
    knob: "shade",
    why: "queues each pattern's hits by atomic appends",
    set: |o| name(o.shade == ShadePasses::PerTexture, o.shade),
    needs: |o| if o.compaction == Compaction::Atomic { None } else { ATOMIC },
};

pub const SORTED: Rule = Rule {
    knob: "shade",
    why: "shades the material queues end to end",
    set: |o| name(o.shade == ShadePasses::Sorted, o.shade),
    needs: queued,
};

/// Its pipeline constant (path_state.wgsl).
pub fn constant(o: &WavefrontOptions) -> (&'static str, f64) {
    ("SHADE_PASSES", o.shade as u32 as f64)
}
