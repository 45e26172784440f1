//! shade (`shaders/wavefront/shade.wgsl`): one pass per material kind the scene uses (and costly
//! pattern), one pass with a material switch, or one over the material queues end to end
//! (`--shade`); each sized on the GPU by queue_setup_shade.

use super::super::stage::Stage;
use super::super::{context::GpuContext, label, shaders};
use super::path_state::{ARGS_PATTERN_0, ARGS_SHADE_0};
use super::{Bindings, ShadePasses, WaveRecorder};
use anyhow::Result;

pub struct Shade {
    /// (argument slot, stage) for each pass to run per bounce.
    stages: Vec<(u64, Stage)>,
}

impl Shade {
    /// `kinds`: material kinds the scene uses (a pass each with `per-material` and
    /// `per-texture`). `patterns` (`--shade per-texture`): the costly patterns with a pass of
    /// their own (indices into `scene::Pattern::ALL`), each compiled with its texture kind alone.
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        mode: ShadePasses,
        kinds: &[u32],
        patterns: &[u32],
        workgroup_size: u32,
        instrument: bool,
    ) -> Result<Self> {
        let module =
            ctx.shader(label::SHADE, shaders::SHADE.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        let passes: Vec<(u64, &'static str)> = match mode {
            ShadePasses::PerMaterial | ShadePasses::PerTexture => {
                kinds.iter().map(|&k| (ARGS_SHADE_0 + k as u64, label::SHADE_BY_KIND[k as usize])).collect()
            }
            ShadePasses::Single => vec![(ARGS_SHADE_0, label::SHADE)],
            ShadePasses::Sorted => vec![(ARGS_SHADE_0, label::SHADE_SORTED)],
        };
        let mut stages: Vec<(u64, Stage)> = passes
            .into_iter()
            .map(|(slot, l)| Ok((slot, Stage::new(ctx, l, &module, &b.layouts(), &constants)?)))
            .collect::<Result<_>>()?;
        for &p in patterns {
            let own = crate::layout::texture_kind::NOISE + p;
            let constants: Vec<(&str, f64)> = constants
                .iter()
                .map(|&(n, v)| if n == "TEXTURE_KINDS" { (n, (1u32 << own) as f64) } else { (n, v) })
                .collect();
            let l = label::SHADE_BY_PATTERN[p as usize];
            stages.push((ARGS_PATTERN_0 + p as u64, Stage::new(ctx, l, &module, &b.layouts(), &constants)?));
        }
        Ok(Self { stages })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        for (slot, stage) in &self.stages {
            let args = wave.consumer(*slot);
            wave.record(stage, Some(bounce), usize::MAX, args);
        }
    }

    pub fn passes(&self) -> usize {
        self.stages.len()
    }
}
