//! `--queue-order`: the order of the paths in the wavefront's queues (`gpu/wavefront/
//! queue_order.rs`, `slot_sweep.rs`, `compact.rs`).

use super::*;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QueueOrder {
    /// Slot order when regenerating with queues a job of at least four pools,
    /// arrival order otherwise: what measured faster (docs/methods.md): the pool-wide scan pays
    /// where many refills scatter the pool, and only costs where waves empty it or a job barely
    /// refills it.
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
enum_values!(QueueOrder);

/// `auto` takes slot order for regenerating jobs of at least this many pools of samples. On
/// llvmpipe (experiments/results/llvmpipe-2core/queue_order) slot order lost at 1.4 pools
/// (400x225x16) and won at 12.4 (1200x675x16) on every scene with atomic appends; 4 lies
/// between, not measured itself.
pub const AUTO_SLOT_POOLS: u64 = 4;

flag! {
    /// Wavefront: keep queues in the order their paths arrived, or build the ray queue in slot
    /// order by a pass over the pool (a subgroup reads neighbouring path states; regenerated
    /// samples fill the lowest free slots): a stable scan with --compaction-method scan, a sweep
    /// of appends (runs of ascending slots) with atomic; optionally keyed by depth (`slot-depth`,
    /// always a scan: a refill's first bounces in one run, as in a wave); `auto`: slot order when
    /// regenerating a job of at least 4 pools of samples, arrival order otherwise.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    queue_order: QueueOrder
}

pub const KNOB: Knob =
    knob!("queue_order", "queue-order", WAVEFRONT, QueueOrder, o => o.wavefront.queue_order);

pub const RULE: Rule = Rule {
    knob: "queue_order",
    why: "orders the queues",
    set: |o| name(o.queue_order.is_slot(), o.queue_order),
    needs: queued,
};

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

    /// Whether the ray queue is built by a pass over the pool's slots (either key).
    pub fn is_slot(self) -> bool {
        matches!(self, QueueOrder::Slot | QueueOrder::SlotDepth)
    }
}
