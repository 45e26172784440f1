//! `--batches-in-flight`: the regenerating host loop's batches of `--sync-every` iterations
//! submitted before it waits for the oldest one's read-back (`gpu/wavefront/schedule.rs`).

use super::*;

/// Default `--batches-in-flight`: batches of `--sync-every` iterations the regenerating host
/// loop keeps in flight (each with its own staging buffer for the counters' read-back): enough
/// that waiting for the oldest leaves newer ones queued, so the GPU never idles for the host
/// inside a share.
pub const BATCHES_IN_FLIGHT: u32 = 3;

/// Most `--batches-in-flight`.
pub const MAX_BATCHES_IN_FLIGHT: u32 = 16;

flag! {
    /// Wavefront, regenerate: batches of --sync-every iterations submitted before the host waits
    /// for the oldest one's read-back (1: it waits for each check, the GPU idle meanwhile, as
    /// before the GPU decided; more: newer batches keep the GPU busy while it waits).
    #[arg(long, default_value_t = BATCHES_IN_FLIGHT, hide_short_help = true)]
    batches_in_flight: u32
}

pub const KNOB: Knob =
    knob!("batches_in_flight", "in_flight", WAVEFRONT, u32, o => o.wavefront.batches_in_flight);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    in_range("batches_in_flight", o.batches_in_flight, 1, MAX_BATCHES_IN_FLIGHT, " batches")
}

pub const RULE: Rule = Rule {
    knob: "batches_in_flight",
    why: "sets the regenerating schedule's batches in flight",
    set: |o| number(o.batches_in_flight != BATCHES_IN_FLIGHT, o.batches_in_flight),
    needs: regenerating,
};
