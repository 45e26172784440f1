//! `--refill`: where the regenerating wavefront starts its next samples (issue 44: generate
//! fused into the passes where paths end; `gpu/wavefront/refill.rs`).

use super::*;

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
enum_values!(Refill);

flag! {
    /// Wavefront, --schedule regenerate: start the next samples in a pass over the free slots
    /// (`pass`), or in the slot of each path that ends, in intersect or shade, as it ends
    /// (`in-place`: generate fused into them; needs --compaction-method atomic and refills at
    /// every iteration).
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    refill: Refill
}

pub const KNOB: Knob = knob!("refill", "refill", WAVEFRONT, Refill, o => o.wavefront.refill);

pub const RULE: Rule = Rule {
    knob: "refill",
    why: "starts samples where paths end, appending their camera rays",
    set: |o| name(o.refill == Refill::InPlace, o.refill),
    needs: |o| {
        regenerating(o)
            .or(if o.compaction == Compaction::Atomic { None } else { ATOMIC })
            .or(if o.refill_below == DEFAULT_REFILL_BELOW { None } else { Some(("refill_below", &["1"])) })
            .or(if o.compact_states == CompactStates::Off {
                None
            } else {
                Some(("compact_states", &["off"]))
            })
    },
};

/// Its pipeline constant (path_state.wgsl): on only where it acts, regenerating.
pub fn constant(o: &WavefrontOptions, regenerate: bool) -> (&'static str, f64) {
    ("REFILL_IN_PLACE", (regenerate && o.refill == Refill::InPlace) as u32 as f64)
}
