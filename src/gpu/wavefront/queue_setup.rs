//! queue_setup (`shaders/wavefront/queue_setup.wgsl`): single-thread passes that turn queue
//! counters into indirect-dispatch arguments, so the host never reads a counter mid-render; and
//! (regenerate) the schedule's decision after each check, on the GPU.

use super::pass::{Binds, Constants, Launch, Pass, Phase, Shader, When};

/// A setup pass: one thread, with scene, path state and the indirect arguments bound.
pub(super) fn pass(label: &'static str, when: When, c: &Constants) -> Pass {
    Pass::new(label, Phase::Iteration, Shader::QueueSetup, Launch::Single, Binds::Indirect)
        .when(when)
        .with(&c.setup)
}

/// (regenerate) A setup pass that ends an iteration with the schedule's decision, with the
/// film range bound too (which it writes for accumulate_range).
pub(super) fn decide(label: &'static str, c: &Constants) -> Pass {
    pass(label, When::Check, c).binds(Binds::Decide)
}
