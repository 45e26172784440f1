//! queue_setup (`shaders/wavefront/queue_setup.wgsl`): single-thread passes that turn queue
//! counters into indirect-dispatch arguments, so the host never reads a counter mid-render; and
//! (regenerate) the schedule's decision after each check, on the GPU.

use super::super::buffers::storage_entry;
use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::{Bindings, WaveRecorder};
use anyhow::Result;

/// (regenerate) The decision pass (`schedule_decide`) and its group 3: the range
/// `accumulate_range` adds, which it writes.
struct Decide {
    stage: Stage,
    /// queue_setup_shadow and the decision in one dispatch (`--nee on`).
    with_shadow: Stage,
    film_range: wgpu::BindGroup,
}

pub struct QueueSetup {
    before_regenerate: Stage,
    before_compact_states: Stage,
    decide: Option<Decide>,
    before_intersect: Stage,
    before_shade: Stage,
    before_shadow: Stage,
}

impl QueueSetup {
    /// `film_range`: the regenerating schedule's accumulate range ([`super::super::accumulate::Accumulate::range_buffer`]).
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        workgroup_size: u32,
        film_range: Option<&wgpu::Buffer>,
    ) -> Result<Self> {
        let module = ctx.shader(label::QUEUE_SETUP_INTERSECT, shaders::QUEUE_SETUP, b.shader_checks)?;
        let mut constants = vec![
            ("WORKGROUP_SIZE", workgroup_size as f64),
            ("STATS_BOUNCES", b.state.stats_bounces as f64),
            // The clamp of every indirect argument (wavefront/shared/indirect_args.wgsl): the device's limit.
            ("MAX_WORKGROUPS", ctx.device.limits().max_compute_workgroups_per_dimension as f64),
        ];
        constants.extend(b.schedule_constants());
        // Scene, path state and the indirect arguments (never the instrument counters).
        let layouts = &[b.layouts()[0], b.layouts()[1], &b.state.indirect_layout];
        let decide = film_range
            .map(|buffer| -> Result<Decide> {
                let range_layout = ctx.bind_group_layout("film range", &[storage_entry(0, false)]);
                let film_range = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("film range"),
                    layout: &range_layout,
                    entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
                });
                let layouts = &[layouts[0], layouts[1], layouts[2], &range_layout];
                let stage = Stage::new(ctx, label::SCHEDULE_DECIDE, &module, layouts, &constants)?;
                let with_shadow =
                    Stage::new(ctx, label::QUEUE_SETUP_SHADOW_DECIDE, &module, layouts, &constants)?;
                Ok(Decide { stage, with_shadow, film_range })
            })
            .transpose()?;
        Ok(Self {
            decide,
            before_regenerate: Stage::new(ctx, label::QUEUE_SETUP_REGENERATE, &module, layouts, &constants)?,
            before_compact_states: Stage::new(
                ctx,
                label::QUEUE_SETUP_COMPACT_STATES,
                &module,
                layouts,
                &constants,
            )?,
            before_intersect: Stage::new(ctx, label::QUEUE_SETUP_INTERSECT, &module, layouts, &constants)?,
            before_shade: Stage::new(ctx, label::QUEUE_SETUP_SHADE, &module, layouts, &constants)?,
            before_shadow: Stage::new(ctx, label::QUEUE_SETUP_SHADOW, &module, layouts, &constants)?,
        })
    }

    pub fn record_regenerate(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        record(&self.before_regenerate, wave, bounce);
    }

    pub fn record_compact_states(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        record(&self.before_compact_states, wave, bounce);
    }

    /// (regenerate) The decision pass after an iteration: sizes the tail and accumulate_range
    /// recorded after it.
    pub fn record_decide(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        let d = self.decide.as_ref().expect("QueueSetup built without the decision pass");
        record_with_range(&d.stage, d, wave, bounce);
    }

    /// (regenerate, `--nee on`) [`Self::record_shadow`] and [`Self::record_decide`] as one
    /// dispatch, before the shadow pass.
    pub fn record_shadow_decide(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        let d = self.decide.as_ref().expect("QueueSetup built without the decision pass");
        record_with_range(&d.with_shadow, d, wave, bounce);
    }

    pub fn record_intersect(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        record(&self.before_intersect, wave, bounce);
    }

    pub fn record_shade(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        record(&self.before_shade, wave, bounce);
    }

    pub fn record_shadow(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        record(&self.before_shadow, wave, bounce);
    }
}

/// Single-thread pass with scene, path state and the indirect arguments bound.
fn record(stage: &Stage, wave: &mut WaveRecorder<'_>, bounce: u32) {
    let indirect = (&wave.b.state.indirect_group, vec![]);
    wave.record_with(stage, Some(bounce), 2, Some(indirect), Workgroups::Direct(1));
}

/// Single-thread pass with scene, path state, the indirect arguments and the film range bound.
fn record_with_range(stage: &Stage, d: &Decide, wave: &mut WaveRecorder<'_>, bounce: u32) {
    let b = wave.b;
    let mut g = b.groups(wave.offset);
    g.truncate(2);
    g.push((&b.state.indirect_group, vec![]));
    g.push((&d.film_range, vec![]));
    wave.record_groups(stage, Some(bounce), &g, Workgroups::Direct(1));
}
