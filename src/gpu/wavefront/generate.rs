//! generate (`shaders/wavefront/generate.wgsl`): camera paths. With `--schedule waves`, one pass
//! starts every path of a wave; with `--schedule regenerate`, `regenerate_init` empties the pool
//! at a share's start and `regenerate` refills the slots whose paths ended, every iteration.

use super::pass::{Binds, Constants, Launch, Pass, Phase, Queue, Shader, When};
use super::path_state::ARGS_REGENERATE;
use super::plan::Plan;
use crate::gpu::label;

/// A share's start: a wave's camera rays (`generate`), or every slot freed (`regenerate_init`).
pub(super) fn start(plan: &Plan, c: &Constants) -> Pass {
    let (l, produces) =
        if plan.regenerate { (label::REGENERATE_INIT, Queue::Free) } else { (label::GENERATE, Queue::Rays) };
    Pass::new(l, Phase::Start, Shader::Generate, Launch::Paths, Binds::Instrumented)
        .with(&[c.workgroup])
        .scene()
        .unbounced()
        .queues(&[], &[produces])
}

/// (regenerate) The refill: the share's next samples into the free slots, sized by
/// queue_setup_regenerate.
pub(super) fn refill(c: &Constants) -> Pass {
    Pass::over_paths(label::REGENERATE, Shader::Generate, Launch::Queue(ARGS_REGENERATE), c)
        .when(When::Refill)
        .queues(&[Queue::Free], &[Queue::Rays])
}
