//! The order of the paths in each queue (`--queue-order`, issue 26). In arrival order a queue
//! lists its paths as the producing pass met them (atomic appends, or the scan over the previous
//! queue's positions), so after a few bounces, and at once after regeneration's refills,
//! neighbouring lanes of a pass read path states scattered over the whole pool: every lane its
//! own cache line. In slot order every scan runs over the pool's slots instead, so each queue
//! lists its paths by slot and a subgroup reads neighbouring states; the same scan lists the free
//! slots in ascending order (the refill then starts consecutive samples in ascending slots) and
//! the pending shadow rays. The price: each scan covers the pool, not only the paths just
//! processed.

use super::Compaction;
use anyhow::{bail, Result};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QueueOrder {
    /// As the producing pass met the paths (the scan keeps the previous queue's order).
    #[default]
    Arrival,
    /// By slot: every queue built by a scan over the pool (needs the scan compaction).
    Slot,
}

impl QueueOrder {
    /// The `order` word of the shaders' `Wave` uniform.
    pub fn word(self) -> u32 {
        match self {
            QueueOrder::Arrival => 0,
            QueueOrder::Slot => 1,
        }
    }

    /// Slot order is what the scan builds: with atomic appends the order is the hardware's.
    pub fn check(self, compaction: Compaction) -> Result<()> {
        if self == QueueOrder::Slot && compaction != Compaction::Scan {
            bail!(
                "--queue-order slot builds every queue with a scan over the pool's slots: it needs \
                 --compaction on --compaction-method scan (atomic appends leave the order to the hardware)"
            );
        }
        Ok(())
    }
}
