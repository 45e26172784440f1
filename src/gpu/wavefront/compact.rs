//! compact (`shaders/wavefront/compact.wgsl`): the prefix-sum scan that builds dense queues when
//! `--compaction-method scan` (the alternative to atomic appends). Three passes over the queue
//! positions the previous pass processed (sized on the GPU by queue_setup): per-workgroup scan,
//! scan of workgroup totals (a workgroup per 1,024 of them), scatter; built twice, for the material queues (after intersect) and
//! for the next ray queue (after shade).

use super::super::context::GpuContext;
use crate::options::Scan;
use anyhow::{bail, Result};

impl Scan {
    /// Whether this scan uses subgroups on `ctx`'s adapter; an error if asked for and missing.
    pub fn uses_subgroups(self, ctx: &GpuContext) -> Result<bool> {
        match self {
            Scan::Auto => Ok(ctx.summary.subgroups),
            Scan::Workgroup => Ok(false),
            Scan::Subgroup if ctx.summary.subgroups => Ok(true),
            Scan::Subgroup => {
                bail!(
                    "--scan subgroup needs subgroup operations, which {} lacks; use --scan auto",
                    ctx.summary.name
                )
            }
        }
    }
}

use super::pass::{Binds, Launch, Pass, Phase, Queue, Shader};
use super::path_state::ARGS_COMPACT;
use super::plan::Plan;
use crate::gpu::label;

/// Which queues a compaction builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// After intersect: one queue per material kind.
    MaterialQueues,
    /// After shade: the next bounce's ray queue (with the free list and the shadow queue).
    NextRayQueue,
}

/// Scan, blocks, scatter, building `target` (scene and path state only).
pub(super) fn passes(plan: &Plan, target: Target) -> Vec<Pass> {
    use Queue::*;
    let rays = target == Target::NextRayQueue;
    let (consumes, produces) =
        if rays { (vec![Slots], vec![Rays, Free, Shadow]) } else { (vec![Rays], vec![Materials]) };
    let args = Launch::Indirect(ARGS_COMPACT);
    [
        (label::COMPACT_SCAN, args),
        (label::COMPACT_BLOCKS, Launch::Direct(plan.scan_blocks)),
        (label::COMPACT_SCATTER, args),
    ]
    .into_iter()
    .map(|(l, launch)| {
        Pass::new(l, Phase::Iteration, Shader::Compact, launch, Binds::State)
            .with(&[("TARGET_RAYS", rays as u32 as f64)])
            .queues(&consumes, &produces)
    })
    .collect()
}
