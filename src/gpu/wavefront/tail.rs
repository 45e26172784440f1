//! tail (`shaders/wavefront/tail.wgsl`, `--tail megakernel`): finishes regenerated paths
//! megakernel-style, in one pass sized on the GPU by the schedule's decision pass
//! (queue_setup.wgsl's schedule_decide): the image's last ones once the live paths fall below a
//! fraction of the pool, and the oldest chunks' last ones when the sample ring needs them back
//! (the paths of samples below the bound it sets).

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_TAIL;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct TailPass {
    stage: Stage,
}

impl TailPass {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32, instrument: bool) -> Result<Self> {
        let module = ctx.shader(label::TAIL, shaders::TAIL.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        Ok(Self { stage: Stage::new(ctx, label::TAIL, &module, &b.layouts(), &constants)? })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>) {
        let args = Workgroups::Indirect(&wave.b.state.indirect, ARGS_TAIL * 12);
        wave.record(&self.stage, None, usize::MAX, args);
    }
}
