//! `--tail-threshold`: the live fraction of the pool below which the megakernel tail takes over.

use super::*;

/// Default `--tail-threshold`: the live fraction of the pool below which the tail takes over.
pub const DEFAULT_THRESHOLD: f64 = 0.05;

flag! {
    /// Wavefront, --tail megakernel: the live fraction of the pool, in (0, 1], below which the
    /// tail takes over.
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, hide_short_help = true)]
    tail_threshold: f64
}

pub const KNOB: Knob =
    knob!("tail_threshold", "tail-threshold", WAVEFRONT, f64, o => o.wavefront.tail_threshold);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    fraction("tail_threshold", o.tail_threshold, "a fraction of the pool")
}

pub const RULE: Rule = Rule {
    knob: "tail_threshold",
    why: "sets when the megakernel tail takes over",
    set: |o| number(o.tail_threshold != DEFAULT_THRESHOLD, o.tail_threshold),
    needs: |o| {
        regenerating(o).or(if o.tail == Tail::Megakernel { None } else { Some(("tail", &["megakernel"])) })
    },
};
