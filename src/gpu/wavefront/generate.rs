//! generate (`shaders/wavefront/generate.wgsl`): a camera ray for every path of a wave.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct Generate {
    stage: Stage,
    workgroup_size: u32,
}

impl Generate {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module = ctx.shader(label::GENERATE, shaders::GENERATE.get(instrument))?;
        let constants = b.scene.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        Ok(Self {
            stage: Stage::new(ctx, label::GENERATE, &module, &b.layouts(), &constants)?,
            workgroup_size,
        })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>) {
        let groups = wave.paths.div_ceil(self.workgroup_size);
        wave.record(&self.stage, None, usize::MAX, Workgroups::Direct(groups));
    }
}
