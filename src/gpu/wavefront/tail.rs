//! tail (`shaders/wavefront/tail.wgsl`, `--tail megakernel`): finishes regenerated paths
//! megakernel-style, in one pass sized on the GPU by the schedule's decision pass
//! (queue_setup.wgsl's schedule_decide): the image's last ones once the live paths fall below a
//! fraction of the pool, and the oldest chunks' last ones when the sample ring needs them back
//! (the paths of samples below the bound it sets).

use super::pass::{Constants, Launch, Pass, Phase, Queue, Shader};
use super::path_state::ARGS_TAIL;
use crate::gpu::label;

/// After a decision that sized it: every live path of the slots it covers, to its end.
pub(super) fn pass(c: &Constants) -> Pass {
    let mut p = Pass::over_paths(label::TAIL, Shader::Tail, Launch::Indirect(ARGS_TAIL), c)
        .unbounced()
        .queues(&[Queue::Slots], &[Queue::Samples]);
    p.phase = Phase::Decided;
    p
}
