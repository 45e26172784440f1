//! `--sync-every`: the regenerating schedule's iterations between checks of its counters, and
//! per batch the host submits (`gpu/wavefront/schedule.rs`).

use super::*;

/// Iterations between checks (and per submitted batch) when regenerating: each check's passes
/// and each batch's submission and read-back cost fixed time; each iteration recorded after the
/// work ran out costs its (empty) dispatches.
pub const DEFAULT_SYNC_EVERY: u32 = 8;

/// Most iterations between read-backs.
pub const MAX_SYNC_EVERY: u32 = 1024;

flag! {
    /// Wavefront, regenerate: iterations between checks of the schedule's counters (on the GPU,
    /// which then adds complete chunks to the film; up to this many iterations idle at the
    /// image's end), and per batch the host submits and reads back without waiting. With --tail
    /// megakernel, the check runs after every iteration once every sample has started, so the
    /// tail starts when it is due.
    #[arg(long, default_value_t = DEFAULT_SYNC_EVERY, hide_short_help = true)]
    sync_every: u32
}

pub const KNOB: Knob = knob!("sync_every", "sync", WAVEFRONT, u32, o => o.wavefront.sync_every);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    in_range("sync_every", o.sync_every, 1, MAX_SYNC_EVERY, " iterations")
}

pub const RULE: Rule = Rule {
    knob: "sync_every",
    why: "sets the iterations between the regenerating schedule's checks",
    set: |o| number(o.sync_every != DEFAULT_SYNC_EVERY, o.sync_every),
    needs: regenerating,
};
