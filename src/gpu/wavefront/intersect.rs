//! intersect (`shaders/wavefront/intersect.wgsl`): closest hits for the bounce's ray queue,
//! sized on the GPU by queue_setup_intersect.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders, timing::GpuTimer};
use super::path_state::ARGS_INTERSECT;
use super::Bindings;
use anyhow::Result;

pub struct Intersect {
    stage: Stage,
}

impl Intersect {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module = ctx.shader(label::INTERSECT, shaders::INTERSECT.get(instrument))?;
        let constants = [("WORKGROUP_SIZE", workgroup_size as f64)];
        Ok(Self { stage: Stage::new(ctx, label::INTERSECT, &module, &b.layouts(), &constants)? })
    }

    pub fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        b: &Bindings,
        offset: u32,
        bounce: u32,
    ) {
        let args = Workgroups::Indirect(&b.state.indirect, ARGS_INTERSECT * 12);
        self.stage.record(enc, timer, Some(bounce), &b.groups(offset), args);
    }
}
