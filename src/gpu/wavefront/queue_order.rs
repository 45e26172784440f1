//! The order of the paths in each queue (`--queue-order`, issue 26). In arrival order a queue
//! lists its paths as the producing pass met them (atomic appends, or the scan over the previous
//! queue's positions), so after a few bounces, and at once after regeneration's refills,
//! neighbouring lanes of a pass read path states scattered over the whole pool: every lane its
//! own cache line. In slot order the ray queue is built after shade by a pass over the pool's
//! slots, so it lists its paths by slot and a subgroup reads neighbouring states: the scan
//! method's stable scan gives exact slot order; the atomic method's sweep (slot_sweep.wgsl),
//! one pass of appends aggregated per subgroup, gives runs of ascending slots, one per
//! subgroup, in the atomics' order, at a third of the scan's cost (three-spheres 1200x675x64 on
//! llvmpipe: 3.79 s against 11.95 s of a ~70 s frame). The material queues keep that order (the
//! stable scan) or its subgroups' runs (atomic appends). The same pass lists the free slots in
//! ascending order, or in ascending runs (the refill then starts consecutive samples in
//! neighbouring slots), and the pending shadow rays. The price: that pass covers the pool, not
//! only the paths just processed. The depth key (`slot-depth`) places one run after all the
//! others, which needs their total: it takes the scan with either method.

use super::{Compaction, Schedule};
use anyhow::{bail, Result};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QueueOrder {
    /// Slot order when regenerating with queues a job of at least four pools,
    /// arrival order otherwise: what measured faster (experiments/queue_order.json): the
    /// pool-wide scan pays where many refills scatter the pool, and only costs where waves empty
    /// it or a job barely refills it.
    #[default]
    Auto,
    /// As the producing pass met the paths (the scan keeps the previous queue's order).
    Arrival,
    /// By slot: the ray queue built by a pass over the pool's slots (needs queues): the scan
    /// method's stable scan, or the atomic method's sweep (runs of ascending slots).
    Slot,
    /// By slot, keyed by depth: the same scan lists the paths about to trace their first bounce
    /// after the camera ray (the last refill's children: consecutive samples) in one run after
    /// the others, as a wave would, rather than interleaved with paths at every depth.
    SlotDepth,
}

/// `auto` takes slot order for regenerating jobs of at least this many pools of samples. On
/// llvmpipe (experiments/results/llvmpipe-2core/queue_order) slot order lost at 1.4 pools
/// (400x225x16) and won at 12.4 (1200x675x16) on every scene with atomic appends; 4 lies
/// between, not measured itself.
pub const AUTO_SLOT_POOLS: u64 = 4;

impl QueueOrder {
    /// The order a render uses, `Arrival` or `Slot`, with this schedule and compaction, for a
    /// job of `samples` samples on a pool of `pool` slots.
    pub fn resolve(self, schedule: Schedule, compaction: Compaction, samples: u64, pool: u32) -> QueueOrder {
        match self {
            QueueOrder::Auto
                if schedule == Schedule::Regenerate
                    && compaction != Compaction::Off
                    && samples >= AUTO_SLOT_POOLS * pool as u64 =>
            {
                QueueOrder::Slot
            }
            QueueOrder::Auto => QueueOrder::Arrival,
            order => order,
        }
    }

    /// The `order` word of the shaders' `Wave` uniform, for a resolved order.
    pub fn word(self) -> u32 {
        match self {
            QueueOrder::Slot => 1,
            QueueOrder::SlotDepth => 2,
            QueueOrder::Auto | QueueOrder::Arrival => 0,
        }
    }

    /// Whether the ray queue is built by a pass over the pool's slots (either key).
    pub fn is_slot(self) -> bool {
        matches!(self, QueueOrder::Slot | QueueOrder::SlotDepth)
    }

    /// The knob's value as users write it.
    pub fn name(self) -> String {
        use clap::ValueEnum;
        self.to_possible_value().expect("every order has a value").get_name().to_owned()
    }

    /// Slot order orders queues: without compaction there are none.
    pub fn check(self, compaction: Compaction) -> Result<()> {
        if self.is_slot() && compaction == Compaction::Off {
            bail!(
                "--queue-order {} orders the queues, and --compaction off has none: use --compaction on",
                self.name()
            );
        }
        Ok(())
    }
}
