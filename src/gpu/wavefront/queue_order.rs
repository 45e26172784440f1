//! The order of the paths in each queue (`--queue-order`, issue 26). In arrival order a queue
//! lists its paths as the producing pass met them (atomic appends, or the scan over the previous
//! queue's positions), so after a few bounces, and at once after regeneration's refills,
//! neighbouring lanes of a pass read path states scattered over the whole pool: every lane its
//! own cache line. In slot order the ray queue is built after shade by a scan over the pool's
//! slots (with either compaction method), so it lists its paths by slot and a subgroup reads
//! neighbouring states; the material queues keep that order (the scan method's stable scan) or
//! its subgroups' runs (atomic appends, aggregated per subgroup). The same scan lists the free
//! slots in ascending order (the refill then starts consecutive samples in ascending slots) and
//! the pending shadow rays. The price: that scan covers the pool, not only the paths just
//! processed.

use super::Compaction;
use anyhow::{bail, Result};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QueueOrder {
    /// As the producing pass met the paths (the scan keeps the previous queue's order).
    #[default]
    Arrival,
    /// By slot: the ray queue built by a scan over the pool's slots (needs queues).
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

    /// Slot order orders queues: without compaction there are none.
    pub fn check(self, compaction: Compaction) -> Result<()> {
        if self == QueueOrder::Slot && compaction == Compaction::Off {
            bail!("--queue-order slot orders the queues, and --compaction off has none: use --compaction on");
        }
        Ok(())
    }
}
