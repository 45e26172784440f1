//! shade (`shaders/wavefront/shade.wgsl`): one pass per material kind the scene uses (and costly
//! pattern), one pass with a material switch, or one over the material queues end to end
//! (`--shade`); each sized on the GPU by queue_setup_shade.

use super::pass::{Constants, Launch, Pass, Queue, Shader};
use super::path_state::{ARGS_PATTERN_0, ARGS_SHADE_0};
use super::plan::Plan;
use super::ShadePasses;
use crate::gpu::label;

/// The shade passes of `mode`: a pass per material kind the scene uses with `per-material`
/// and `per-texture`, and with `per-texture` a pass per costly pattern (`plan.patterns`: indices
/// into `scene::Pattern::ALL`), each compiled with its texture kind alone; one pass with a
/// switch; or one over the material queues end to end.
pub(super) fn passes(plan: &Plan, mode: ShadePasses, c: &Constants) -> Vec<Pass> {
    // Paths going on, and those that end (their samples finished).
    let mut produces = vec![Queue::Rays, Queue::Samples];
    if plan.regenerate {
        produces.push(Queue::Free);
    }
    if plan.shadow_pass {
        produces.push(Queue::Shadow);
    }
    let pass = |l, slot, consumes| {
        Pass::over_paths(l, Shader::Shade, Launch::Queue(slot), c)
            .with(&[("SHADOW_INLINE", plan.inline_shadow as u32 as f64), c.stats_bounces])
            .queues(&[consumes], &produces)
    };
    let mut p: Vec<Pass> = match mode {
        ShadePasses::PerMaterial | ShadePasses::PerTexture => plan
            .kinds
            .iter()
            .map(|&k| pass(label::SHADE_BY_KIND[k as usize], ARGS_SHADE_0 + k as u64, Queue::Materials))
            .collect(),
        ShadePasses::Single => vec![pass(label::SHADE, ARGS_SHADE_0, Queue::Materials)],
        ShadePasses::Sorted => vec![pass(label::SHADE_SORTED, ARGS_SHADE_0, Queue::Materials)],
    };
    for &pattern in &plan.patterns {
        let own = crate::layout::texture_kind::NOISE + pattern;
        let l = label::SHADE_BY_PATTERN[pattern as usize];
        p.push(
            pass(l, ARGS_PATTERN_0 + pattern as u64, Queue::Patterns)
                .with(&[("TEXTURE_KINDS", (1u32 << own) as f64)]),
        );
    }
    p
}
