//! `--refill-below`: the live fraction of the pool at or below which the regenerating schedule
//! refills it (`gpu/wavefront/refill.rs`).

use super::*;

/// Default `--refill-below`: refill at every iteration, whatever is live.
pub const DEFAULT_REFILL_BELOW: f64 = 1.0;

flag! {
    /// Wavefront, --schedule regenerate: refill the pool only once at most this fraction of it,
    /// in (0, 1], is live (1: at every iteration, into whatever slots paths just left; less:
    /// larger batches of consecutive samples, as Cycles schedules new work only when too few
    /// paths are left).
    #[arg(long, default_value_t = DEFAULT_REFILL_BELOW, hide_short_help = true)]
    refill_below: f64
}

pub const KNOB: Knob = knob!("refill_below", "refill-below", WAVEFRONT, f64, o => o.wavefront.refill_below);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    fraction("refill_below", o.refill_below, "a live fraction of the pool")
}

pub const RULE: Rule = Rule {
    knob: "refill_below",
    why: "batches the refills of regenerated paths",
    set: |o| number(o.refill_below != DEFAULT_REFILL_BELOW, o.refill_below),
    needs: regenerating,
};
