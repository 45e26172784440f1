//! intersect (`shaders/wavefront/intersect.wgsl`): closest hits for the bounce's ray queue,
//! sized on the GPU by queue_setup_intersect.

use super::super::stage::Stage;
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_INTERSECT;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct Intersect {
    stage: Stage,
}

impl Intersect {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module =
            ctx.shader(label::INTERSECT, shaders::INTERSECT.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        Ok(Self { stage: Stage::new(ctx, label::INTERSECT, &module, &b.layouts(), &constants)? })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        let args = wave.consumer(ARGS_INTERSECT);
        wave.record(&self.stage, Some(bounce), usize::MAX, args);
    }
}
