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

use crate::options::QueueOrder;

impl QueueOrder {
    /// The `order` word of the shaders' `Wave` uniform, for a resolved order.
    pub fn word(self) -> u32 {
        match self {
            QueueOrder::Slot => 1,
            QueueOrder::SlotDepth => 2,
            QueueOrder::Auto | QueueOrder::Arrival => 0,
        }
    }
}
