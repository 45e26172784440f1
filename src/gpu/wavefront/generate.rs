//! generate (`shaders/wavefront/generate.wgsl`): a camera ray for every path of a wave.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders, timing::GpuTimer};
use super::Bindings;
use anyhow::Result;

pub struct Generate {
    stage: Stage,
    workgroup_size: u32,
}

impl Generate {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module = ctx.shader(label::GENERATE, shaders::GENERATE.get(instrument))?;
        let constants = [("WORKGROUP_SIZE", workgroup_size as f64)];
        Ok(Self {
            stage: Stage::new(ctx, label::GENERATE, &module, &b.layouts(), &constants)?,
            workgroup_size,
        })
    }

    pub fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        b: &Bindings,
        offset: u32,
        paths: u32,
    ) {
        let groups = paths.div_ceil(self.workgroup_size);
        self.stage.record(enc, timer, None, &b.groups(offset), Workgroups::Direct(groups));
    }
}
