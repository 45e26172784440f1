//! shadow (`shaders/wavefront/shadow.wgsl`): the shadow rays of next-event estimation, one
//! any-hit query per queued ray, sized on the GPU by queue_setup_shadow. Recorded only with
//! `--nee on` in a scene with lights.

use super::pass::{Constants, Launch, Pass, Queue, Shader, When};
use super::path_state::ARGS_SHADOW;
use super::plan::Plan;
use super::queue_setup;
use crate::gpu::label;

/// Its setup (regenerating, with the decision folded in on the iterations that check), then
/// the any-hit queries.
pub(super) fn passes(plan: &Plan, c: &Constants) -> Vec<Pass> {
    let mut p = if plan.regenerate {
        vec![
            queue_setup::pass(label::QUEUE_SETUP_SHADOW, When::NoCheck, c),
            queue_setup::decide(label::QUEUE_SETUP_SHADOW_DECIDE, c),
        ]
    } else {
        vec![queue_setup::pass(label::QUEUE_SETUP_SHADOW, When::Always, c)]
    };
    p.push(
        Pass::over_paths(label::SHADOW, Shader::Shadow, Launch::Queue(ARGS_SHADOW), c)
            .queues(&[Queue::Shadow], &[]),
    );
    p
}
