//! shadow (`shaders/wavefront/shadow.wgsl`): the shadow rays of next-event estimation, one
//! any-hit query per queued ray, sized on the GPU by queue_setup_shadow. Recorded only with
//! `--nee on` in a scene with lights.

use super::super::stage::Stage;
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_SHADOW;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct Shadow {
    stage: Stage,
}

impl Shadow {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module =
            ctx.shader(label::SHADOW, shaders::SHADOW.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        Ok(Self { stage: Stage::new(ctx, label::SHADOW, &module, &b.layouts(), &constants)? })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        let args = wave.consumer(ARGS_SHADOW);
        wave.record(&self.stage, Some(bounce), usize::MAX, args);
    }
}
