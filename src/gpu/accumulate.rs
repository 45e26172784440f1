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
                storage_entry(3, true),
            ],
        );
        let range = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("accumulate range"),
            contents: bytemuck::bytes_of(&AccumulateRange::default()),
            // Written by the regenerating wavefront's decision pass (storage there too).
            usage: wgpu::BufferUsages::STORAGE,
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

    /// `accumulate_range` and its bind group at the share's `offset`, for the regenerating
    /// wavefront to record as an indirect pass sized by its decision pass.
    pub fn range_pass(&self, offset: u32) -> (&Stage, [(&wgpu::BindGroup, Vec<u32>); 1]) {
        let stage = self.range_stage.as_ref().expect("Accumulate built without ranges");
        (stage, [(&self.bind_group, vec![offset])])
    }

    /// The range `accumulate_range` adds ([`AccumulateRange`]), written on the GPU by the
    /// regenerating wavefront's decision pass.
    pub fn range_buffer(&self) -> &wgpu::Buffer {
        &self.range
    }
}
