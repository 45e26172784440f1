//! generate (`shaders/wavefront/generate.wgsl`): camera paths. With `--schedule waves`, one pass
//! starts every path of a wave; with `--schedule regenerate`, `regenerate_init` empties the pool
//! at a share's start and `regenerate` refills the slots whose paths ended, every iteration.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_REGENERATE;
use super::{Bindings, RunSchedule, WaveRecorder};
use anyhow::Result;

pub enum Generate {
    Waves { generate: Stage, workgroup_size: u32 },
    Regenerate { init: Stage, refill: Stage, workgroup_size: u32, pool: u32 },
}

impl Generate {
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        schedule: RunSchedule,
        pool: u32,
        workgroup_size: u32,
        instrument: bool,
    ) -> Result<Self> {
        let module =
            ctx.shader(label::GENERATE, shaders::GENERATE.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        let stage = |l| Stage::new(ctx, l, &module, &b.layouts(), &constants);
        Ok(match schedule {
            RunSchedule::Waves => Generate::Waves { generate: stage(label::GENERATE)?, workgroup_size },
            RunSchedule::Regenerate => Generate::Regenerate {
                init: stage(label::REGENERATE_INIT)?,
                refill: stage(label::REGENERATE)?,
                workgroup_size,
                pool,
            },
        })
    }

    /// Waves: the wave's camera paths. Regenerating: a share's start (every slot free).
    pub fn record_start(&self, wave: &mut WaveRecorder<'_>) {
        let (stage, threads, wg) = match self {
            Generate::Waves { generate, workgroup_size } => (generate, wave.paths, *workgroup_size),
            Generate::Regenerate { init, workgroup_size, pool, .. } => (init, *pool, *workgroup_size),
        };
        wave.record(stage, None, usize::MAX, Workgroups::Direct(threads.div_ceil(wg)));
    }

    /// Regenerating: the refill, sized by queue_setup_regenerate (nothing in waves).
    pub fn record_refill(&self, wave: &mut WaveRecorder<'_>, iteration: u32) {
        if let Generate::Regenerate { refill, .. } = self {
            let args = wave.consumer(ARGS_REGENERATE);
            wave.record(refill, Some(iteration), usize::MAX, args);
        }
    }
}
