//! compact (`shaders/wavefront/compact.wgsl`): the prefix-sum scan that builds dense queues when
//! `--compaction-method scan` (the alternative to atomic appends). Three passes over the queue
//! positions the previous pass processed (sized on the GPU by queue_setup): per-workgroup scan,
//! scan of workgroup totals (a workgroup per 1,024 of them), scatter; built twice, for the material queues (after intersect) and
//! for the next ray queue (after shade).

use super::super::shaders::{self, Hook};
use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label};
use super::path_state::{scan_block_groups, ARGS_COMPACT};
use super::{Bindings, WaveRecorder};

/// Which queues a compaction builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// After intersect: one queue per material kind.
    MaterialQueues,
    /// After shade: the next bounce's ray queue.
    NextRayQueue,
}
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

pub struct Compact {
    /// [scan, blocks, scatter] for the material queues, then for the ray queue.
    to_materials: [Stage; 3],
    to_rays: [Stage; 3],
}

impl Compact {
    pub fn new(ctx: &GpuContext, b: &Bindings, subgroups: bool) -> Result<Self> {
        let source = shaders::COMPACT.select(&[(Hook::ScanSubgroup, subgroups)]);
        let module = ctx.shader(label::COMPACT_SCAN, source, b.shader_checks)?;
        let layouts = &b.layouts()[..2];
        let build = |rays: bool| -> Result<[Stage; 3]> {
            let mut c = vec![("TARGET_RAYS", rays as u32 as f64)];
            c.extend(b.schedule_constants());
            Ok([
                Stage::new(ctx, label::COMPACT_SCAN, &module, layouts, &c)?,
                Stage::new(ctx, label::COMPACT_BLOCKS, &module, layouts, &c)?,
                Stage::new(ctx, label::COMPACT_SCATTER, &module, layouts, &c)?,
            ])
        };
        Ok(Self { to_materials: build(false)?, to_rays: build(true)? })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32, target: Target) {
        let [scan, blocks, scatter] = match target {
            Target::MaterialQueues => &self.to_materials,
            Target::NextRayQueue => &self.to_rays,
        };
        let args = || Workgroups::Indirect(&wave.b.state.indirect, ARGS_COMPACT * 12);
        // Scene and path state only.
        let (scan_args, scatter_args) = (args(), args());
        wave.record(scan, Some(bounce), 2, scan_args);
        let groups = scan_block_groups(wave.b.state.pool as u64) as u32;
        wave.record(blocks, Some(bounce), 2, Workgroups::Direct(groups));
        wave.record(scatter, Some(bounce), 2, scatter_args);
    }
}
