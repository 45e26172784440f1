//! intersect (`shaders/wavefront/intersect.wgsl`): closest hits for the bounce's ray queue,
//! sized on the GPU by queue_setup_intersect.

use super::pass::{Constants, Launch, Pass, Queue, Shader};
use super::path_state::ARGS_INTERSECT;
use super::plan::Plan;
use crate::gpu::label;

/// Closest hits of the ray queue: hits onto the material (or pattern) queues; an escaped path
/// ends (its sample finished) and, regenerating, its slot goes onto the free list.
pub(super) fn pass(plan: &Plan, c: &Constants) -> Pass {
    let mut produces = vec![Queue::Materials, Queue::Samples];
    if !plan.patterns.is_empty() {
        produces.push(Queue::Patterns);
    }
    if plan.regenerate {
        produces.push(Queue::Free);
    }
    Pass::over_paths(label::INTERSECT, Shader::Intersect, Launch::Queue(ARGS_INTERSECT), c)
        .queues(&[Queue::Rays], &produces)
}
