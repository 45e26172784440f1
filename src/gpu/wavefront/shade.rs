//! shade (`shaders/wavefront/shade.wgsl`): one pass per material kind the scene uses, or one
//! pass with a material switch; each sized on the GPU by queue_setup_shade.

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_SHADE_0;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct Shade {
    /// (argument slot, stage) for each pass to run per bounce.
    stages: Vec<(u64, Stage)>,
}

impl Shade {
    /// `kinds`: material kinds the scene uses; `None` builds the single switch pass.
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        kinds: Option<&[u32]>,
        workgroup_size: u32,
        instrument: bool,
    ) -> Result<Self> {
        let module =
            ctx.shader(label::SHADE, shaders::SHADE.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        let passes: Vec<(u64, &'static str)> = match kinds {
            Some(kinds) => {
                kinds.iter().map(|&k| (ARGS_SHADE_0 + k as u64, label::SHADE_BY_KIND[k as usize])).collect()
            }
            None => vec![(ARGS_SHADE_0, label::SHADE)],
        };
        let stages = passes
            .into_iter()
            .map(|(slot, l)| Ok((slot, Stage::new(ctx, l, &module, &b.layouts(), &constants)?)))
            .collect::<Result<_>>()?;
        Ok(Self { stages })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        for (slot, stage) in &self.stages {
            let args = Workgroups::Indirect(&wave.b.state.indirect, slot * 12);
            wave.record(stage, Some(bounce), usize::MAX, args);
        }
    }

    pub fn passes(&self) -> usize {
        self.stages.len()
    }
}
