//! The accumulate pass (`shaders/accumulate.wgsl`): adds one dispatch's per-sample radiance to
//! the film in sample order, or (the regenerating wavefront) a range of its samples from the
//! sample ring. Shared by the GPU methods, so film arithmetic is identical for all.

use super::buffers::{storage_entry, uniform_entry};
use super::context::GpuContext;
use super::dispatch_plan::DispatchUniforms;
use super::stage::{Stage, Workgroups};
use super::timing::GpuTimer;
use super::{label, shaders};
use crate::layout::AccumulateRange;
use anyhow::Result;
use wgpu::util::DeviceExt;

pub const WORKGROUP_SIZE: u32 = 64;

pub struct Accumulate {
    stage: Stage,
    /// `accumulate_range`, built only for the renders that use it (the regenerating wavefront).
    range_stage: Option<Stage>,
    bind_group: wgpu::BindGroup,
    range: wgpu::Buffer,
}

impl Accumulate {
    pub fn new(
        ctx: &GpuContext,
        samples: &wgpu::Buffer,
        film: &wgpu::Buffer,
        params: &DispatchUniforms,
        ranges: bool,
        checks: super::shader_checks::ShaderChecks,
    ) -> Result<Self> {
        let layout = ctx.bind_group_layout(
            label::ACCUMULATE,
            &[
                storage_entry(0, true),
                storage_entry(1, false),
                uniform_entry(2, true),
                uniform_entry(3, false),
            ],
        );
        let range = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("accumulate range"),
            contents: bytemuck::bytes_of(&AccumulateRange::default()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label::ACCUMULATE),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: samples.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: film.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: params.binding() },
                wgpu::BindGroupEntry { binding: 3, resource: range.as_entire_binding() },
            ],
        });
        let module = ctx.shader(label::ACCUMULATE, shaders::ACCUMULATE, checks)?;
        Ok(Self {
            stage: Stage::new(ctx, label::ACCUMULATE, &module, &[&layout], &[])?,
            range_stage: ranges
                .then(|| Stage::new(ctx, label::ACCUMULATE_RANGE, &module, &[&layout], &[]))
                .transpose()?,
            bind_group,
            range,
        })
    }

    /// Records the pass for the dispatch whose parameters sit at `offset` and cover `pixels`.
    pub fn record(&self, enc: &mut wgpu::CommandEncoder, timer: &mut GpuTimer, offset: u32, pixels: u32) {
        let groups = [(&self.bind_group, vec![offset])];
        self.stage.record(enc, timer, None, &groups, Workgroups::Direct(pixels.div_ceil(WORKGROUP_SIZE)));
    }

    /// Records the pass over `range` of the share at `offset` covering `pixels`. The range is
    /// written with the queue, so it takes effect at the next submission: at most one range pass
    /// per submission, recorded before it.
    pub fn record_range(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        offset: u32,
        pixels: u32,
        range: AccumulateRange,
    ) {
        ctx.queue.write_buffer(&self.range, 0, bytemuck::bytes_of(&range));
        let groups = [(&self.bind_group, vec![offset])];
        let threads = pixels.min(range.count);
        let stage = self.range_stage.as_ref().expect("Accumulate built without ranges");
        stage.record(enc, timer, None, &groups, Workgroups::Direct(threads.div_ceil(WORKGROUP_SIZE)));
    }
}
