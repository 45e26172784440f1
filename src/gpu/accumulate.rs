//! The accumulate pass (`shaders/accumulate.wgsl`): adds one dispatch's per-sample radiance to
//! the film in sample order. Shared by the GPU methods, so film arithmetic is identical for all.

use super::buffers::{storage_entry, uniform_entry};
use super::context::GpuContext;
use super::dispatch_plan::DispatchUniforms;
use super::stage::{Stage, Workgroups};
use super::timing::GpuTimer;
use super::{label, shaders};
use anyhow::Result;

pub const WORKGROUP_SIZE: u32 = 64;

pub struct Accumulate {
    stage: Stage,
    bind_group: wgpu::BindGroup,
}

impl Accumulate {
    pub fn new(
        ctx: &GpuContext,
        samples: &wgpu::Buffer,
        film: &wgpu::Buffer,
        params: &DispatchUniforms,
    ) -> Result<Self> {
        let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label::ACCUMULATE),
            entries: &[storage_entry(0, true), storage_entry(1, false), uniform_entry(2, true)],
        });
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label::ACCUMULATE),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: samples.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: film.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: params.binding() },
            ],
        });
        let module = ctx.shader(label::ACCUMULATE, shaders::ACCUMULATE)?;
        Ok(Self { stage: Stage::new(ctx, label::ACCUMULATE, &module, &[&layout], &[])?, bind_group })
    }

    /// Records the pass for the dispatch whose parameters sit at `offset` and cover `pixels`.
    pub fn record(&self, enc: &mut wgpu::CommandEncoder, timer: &mut GpuTimer, offset: u32, pixels: u32) {
        let groups = [(&self.bind_group, vec![offset])];
        self.stage.record(enc, timer, None, &groups, Workgroups::Direct(pixels.div_ceil(WORKGROUP_SIZE)));
    }
}
