//! How the regenerating wavefront refills its pool (issue 26): at every iteration, into whatever
//! slots paths just left (the default), or in batches (`--refill-below F`: only once at most
//! F × pool paths are live, Cycles' rule of scheduling new work only when too few paths are left
//! to keep the device busy), optionally compacting the live states first (`--compact-states on`:
//! Cycles' `compact_states`, `shaders/wavefront/compact_states.wgsl`), so that a batch of
//! consecutive samples takes one contiguous run of slots, as a wave does.

use super::{Compaction, Schedule};
use anyhow::{bail, Result};

/// Default `--refill-below`: refill at every iteration, whatever is live.
pub const DEFAULT_REFILL_BELOW: f64 = 1.0;

/// Whether live path states are compacted below the live count before each refill.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CompactStates {
    /// Refills take the free slots wherever they are.
    Off,
    /// Before each refill, move the live paths above the live count into the free slots below
    /// it, so the refill's consecutive samples take one contiguous run of slots.
    On,
}

/// Refuses refill knobs that mean nothing for this render, naming the knob.
pub fn check(below: f64, compact: CompactStates, schedule: Schedule, compaction: Compaction) -> Result<()> {
    if !(below > 0.0 && below <= 1.0) {
        bail!("--refill-below must be a live fraction of the pool in (0, 1], got {below}");
    }
    let regenerate = schedule == Schedule::Regenerate;
    if below != DEFAULT_REFILL_BELOW && !regenerate {
        bail!(
            "--refill-below {below} batches the refills of regenerated paths: it needs --schedule regenerate"
        );
    }
    if compact == CompactStates::On && !regenerate {
        bail!("--compact-states on compacts the pool before refills: it needs --schedule regenerate");
    }
    if compact == CompactStates::On && compaction == Compaction::Off {
        bail!(
            "--compact-states on rewrites the ray queue's entries of the paths it moves, and --compaction off \
             has no queues: use --compaction on"
        );
    }
    Ok(())
}

/// The most live paths at which a refill runs: `below` × `pool`, rounded down (the whole pool at
/// 1, so every iteration refills).
pub fn refill_live(below: f64, pool: u32) -> u32 {
    (below * pool as f64).floor().clamp(0.0, pool as f64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refill_live_is_a_share_of_the_pool() {
        assert_eq!(refill_live(1.0, 1000), 1000);
        assert_eq!(refill_live(0.5, 1001), 500);
        assert_eq!(refill_live(1e-9, 1000), 0, "a tiny fraction refills only an empty pool");
    }

    #[test]
    fn knobs_are_checked_with_the_reason() {
        let (regen, waves, on, off) =
            (Schedule::Regenerate, Schedule::Waves, CompactStates::On, CompactStates::Off);
        assert!(check(0.5, on, regen, Compaction::Atomic).is_ok());
        assert!(check(1.0, off, waves, Compaction::Off).is_ok());
        for (below, compact, schedule, compaction, says) in [
            (0.0, off, regen, Compaction::Atomic, "in (0, 1], got 0"),
            (1.5, off, regen, Compaction::Atomic, "in (0, 1], got 1.5"),
            (f64::NAN, off, regen, Compaction::Atomic, "got NaN"),
            (0.5, off, waves, Compaction::Atomic, "--refill-below 0.5 batches"),
            (1.0, on, waves, Compaction::Atomic, "needs --schedule regenerate"),
            (1.0, on, regen, Compaction::Off, "use --compaction on"),
        ] {
            let e = check(below, compact, schedule, compaction).unwrap_err().to_string();
            assert!(e.contains(says), "{e}");
        }
    }
}
