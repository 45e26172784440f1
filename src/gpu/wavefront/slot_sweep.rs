//! slot_sweep (`shaders/wavefront/slot_sweep.wgsl`): slot order's queues with the atomic
//! compaction method. One pass over the pool's slots after shade appends each to the next ray
//! queue, the free list (regenerate) or the shadow queue; appends aggregated per subgroup keep
//! each subgroup's slots together in ascending order, so later passes read as few lines of path
//! state as in the scan's exact slot order (though not as one ascending stream), without the
//! scan's three passes and their barriers. Sized on the GPU by queue_setup_shade (the scan's arguments: every slot).

use super::pass::{Binds, Launch, Pass, Phase, Queue, Shader};
use super::path_state::ARGS_COMPACT;
use crate::gpu::label;

/// Over every slot after shade (sized as the scan: every slot), scene and path state only.
pub(super) fn pass() -> Pass {
    Pass::new(
        label::SLOT_SWEEP,
        Phase::Iteration,
        Shader::SlotSweep,
        Launch::Indirect(ARGS_COMPACT),
        Binds::State,
    )
    .queues(&[Queue::Slots], &[Queue::Rays, Queue::Free, Queue::Shadow])
}
