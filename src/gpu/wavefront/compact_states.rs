//! compact_states (`shaders/wavefront/compact_states.wgsl`, `--compact-states on`): before each
//! refill, the live paths above the live count move into the free slots below it, so the
//! refill's consecutive samples take the contiguous slots from the live count on. Three passes,
//! sized on the GPU (queue_setup_regenerate sizes the first; they dispatch nothing on iterations
//! that do not refill).

use super::pass::{Binds, Constants, Launch, Pass, Phase, Queue, Shader, When};
use super::path_state::{ARGS_COMPACT_STATES_FIND, ARGS_COMPACT_STATES_MOVE};
use crate::gpu::label;

/// Find, its setup, move: between queue_setup_regenerate and the refill.
pub(super) fn passes(c: &Constants) -> [Pass; 3] {
    let pass = |l, args| {
        Pass::new(l, Phase::Iteration, Shader::CompactStates, Launch::Indirect(args), Binds::State)
            .when(When::Refill)
            .with(&[c.workgroup])
            .scene()
            .queues(&[Queue::Rays, Queue::Free], &[Queue::Rays, Queue::Free])
    };
    [
        pass(label::COMPACT_STATES_FIND, ARGS_COMPACT_STATES_FIND),
        super::queue_setup::pass(label::QUEUE_SETUP_COMPACT_STATES, When::Refill, c),
        pass(label::COMPACT_STATES_MOVE, ARGS_COMPACT_STATES_MOVE),
    ]
}
