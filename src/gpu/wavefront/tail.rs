//! tail (`shaders/wavefront/tail.wgsl`, `--tail megakernel`): finishes regenerated paths
//! megakernel-style, in one pass sized on the GPU by the schedule's decision pass
//! (queue_setup.wgsl's schedule_decide): the image's last ones once the live paths fall below a
//! fraction of the pool, and the oldest chunks' last ones when the sample ring needs them back
//! (the paths of samples below the bound it sets).

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_TAIL;
use super::{Bindings, WaveRecorder};
use anyhow::{bail, Result};

/// Whether regenerated paths end with a megakernel pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tail {
    /// Iterate the passes until the last path ends.
    Off,
    /// Once the live paths are fewer than `tail_threshold` × pool, finish them in one pass.
    Megakernel,
}

/// Default `--tail-threshold`: the live fraction of the pool below which the tail takes over.
pub const DEFAULT_THRESHOLD: f64 = 0.05;

pub fn check_threshold(t: f64) -> Result<()> {
    if !(t > 0.0 && t <= 1.0) {
        bail!("--tail-threshold must be a fraction of the pool in (0, 1], got {t}");
    }
    Ok(())
}

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
