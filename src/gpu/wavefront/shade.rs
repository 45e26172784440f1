//! shade (`shaders/wavefront/shade.wgsl`): one pass per material kind the scene uses (and costly
//! pattern), one pass with a material switch, or one over the material queues end to end
//! (`--shade`); each sized on the GPU by queue_setup_shade.

use super::super::stage::Stage;
use super::super::{context::GpuContext, label, shaders};
use super::path_state::{ARGS_PATTERN_0, ARGS_SHADE_0};
use super::plan::Plan;
use super::{Bindings, ShadePasses, WaveRecorder};
use anyhow::Result;

pub struct Shade {
    /// (argument slot, stage) for each pass to run per bounce.
    stages: Vec<(u64, Stage)>,
}

impl Shade {
    /// The shade passes of `mode` for `plan`: a pass per material kind the scene uses with
    /// `per-material` and `per-texture`, and with `per-texture` a pass per costly pattern
    /// (`plan.patterns`: indices into `scene::Pattern::ALL`), each compiled with its texture kind
    /// alone; the shadow rays traced inline where `plan.inline_shadow`.
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        plan: &Plan,
        mode: ShadePasses,
        workgroup_size: u32,
        instrument: bool,
    ) -> Result<Self> {
        let (kinds, patterns, inline_shadow) = (&plan.kinds, &plan.patterns, plan.inline_shadow);
        let module =
            ctx.shader(label::SHADE, shaders::SHADE.select(&b.hooks(instrument)), b.shader_checks)?;
        let constants = b.constants(&[
            ("WORKGROUP_SIZE", workgroup_size as f64),
            ("SHADOW_INLINE", inline_shadow as u32 as f64),
            ("STATS_BOUNCES", b.state.stats_bounces as f64),
        ]);
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
