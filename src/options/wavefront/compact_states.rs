//! `--compact-states`: whether the regenerating wavefront compacts its live path states before
//! each refill (Cycles' compact_states; `gpu/wavefront/compact_states.rs`).

use super::*;

/// Whether live path states are compacted below the live count before each refill.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CompactStates {
    /// Refills take the free slots wherever they are.
    #[default]
    Off,
    /// Before each refill, move the live paths above the live count into the free slots below
    /// it, so the refill's consecutive samples take one contiguous run of slots.
    On,
}
enum_values!(CompactStates);

flag! {
    /// Wavefront, --schedule regenerate: before each refill, move the live paths above the live
    /// count into the free slots below it (Cycles' compact_states), so the refill's consecutive
    /// samples take one contiguous run of slots. Needs --compaction on.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    compact_states: CompactStates
}

pub const KNOB: Knob =
    knob!("compact_states", "compact-states", WAVEFRONT, CompactStates, o => o.wavefront.compact_states);

pub const REGENERATING: Rule = Rule {
    knob: "compact_states",
    why: "compacts the pool before refills",
    set: |o| name(o.compact_states == CompactStates::On, o.compact_states),
    needs: regenerating,
};

pub const QUEUED: Rule = Rule {
    knob: "compact_states",
    why: "rewrites the ray queue's entries of the paths it moves",
    set: |o| name(o.compact_states == CompactStates::On, o.compact_states),
    needs: queued,
};

/// Its pipeline constant (path_state.wgsl).
pub fn constant(o: &WavefrontOptions) -> (&'static str, f64) {
    ("COMPACT_STATES", (o.compact_states == CompactStates::On) as u32 as f64)
}
