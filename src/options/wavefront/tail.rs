//! `--tail`: whether the regenerating wavefront finishes its last paths in one megakernel-style
//! pass (`gpu/wavefront/tail.rs`).

use super::*;

/// Whether regenerated paths end with a megakernel pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tail {
    /// Iterate the passes until the last path ends.
    #[default]
    Off,
    /// Once the live paths are fewer than `tail_threshold` × pool, finish them in one pass.
    Megakernel,
}
enum_values!(Tail);

flag! {
    /// Wavefront, regenerate: finish paths in one megakernel-style pass: the image's last ones
    /// once at most --tail-threshold × pool are left, and the oldest chunks' last ones (each at
    /// most that many) when the sample ring would stop the refills.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    tail: Tail
}

pub const KNOB: Knob = knob!("tail", "tail", WAVEFRONT, Tail, o => o.wavefront.tail);

pub const RULE: Rule = Rule {
    knob: "tail",
    why: "finishes regenerated paths",
    set: |o| name(o.tail == Tail::Megakernel, o.tail),
    needs: regenerating,
};
