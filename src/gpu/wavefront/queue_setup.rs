//! queue_setup (`shaders/wavefront/queue_setup.wgsl`): single-thread passes that turn queue
//! counters into indirect-dispatch arguments, so the host never reads a counter mid-render.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders, timing::GpuTimer};
use super::Bindings;
use anyhow::Result;

pub struct QueueSetup {
    before_intersect: Stage,
    before_shade: Stage,
}

impl QueueSetup {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32) -> Result<Self> {
        let module = ctx.shader(label::QUEUE_SETUP_INTERSECT, shaders::QUEUE_SETUP)?;
        let constants =
            [("WORKGROUP_SIZE", workgroup_size as f64), ("STATS_BOUNCES", b.state.stats_bounces as f64)];
        // Scene, path state and the indirect arguments (never the instrument counters).
        let layouts = &[b.layouts()[0], b.layouts()[1], &b.state.indirect_layout];
        Ok(Self {
            before_intersect: Stage::new(ctx, label::QUEUE_SETUP_INTERSECT, &module, layouts, &constants)?,
            before_shade: Stage::new(ctx, label::QUEUE_SETUP_SHADE, &module, layouts, &constants)?,
        })
    }

    pub fn record_intersect(
        &self,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        b: &Bindings,
        offset: u32,
        bounce: u32,
    ) {
        self.before_intersect.record(enc, timer, Some(bounce), &groups(b, offset), Workgroups::Direct(1));
    }

    pub fn record_shade(
        &self,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        b: &Bindings,
        offset: u32,
        bounce: u32,
    ) {
        self.before_shade.record(enc, timer, Some(bounce), &groups(b, offset), Workgroups::Direct(1));
    }
}

fn groups(b: &Bindings, offset: u32) -> Vec<(&wgpu::BindGroup, Vec<u32>)> {
    let mut g = b.groups(offset);
    g.truncate(2);
    g.push((&b.state.indirect_group, vec![]));
    g
}
