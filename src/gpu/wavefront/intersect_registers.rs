//! intersect_registers (`shaders/wavefront/intersect_registers.wgsl`): the diagnostic twin of
//! the intersect pass that makes each camera ray in place and keeps only a tally of its hits, no
//! path state read or written (issue 44, item 1b). `measure::intersect_cost` times it beside the
//! wavefront's own intersect of the same camera rays.

use anyhow::{bail, Result};
use wgpu::util::DeviceExt;

use super::super::buffers::{storage_entry, storage_zeroed, uniform_entry, Staging};
use super::super::scene_buffers::SceneBuffers;
use super::super::shader_checks::ShaderChecks;
use super::super::timing::GpuTimer;
use super::super::{context::GpuContext, label, shaders};

/// What the pass found: hits among the camera rays, and the wrapping sum of (hit primitive + 1)
/// over them (the same rays give the same sum, whatever order the lanes take them in).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Tally {
    pub hits: u64,
    pub checksum: u32,
}

pub struct IntersectRegisters {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    tally: wgpu::Buffer,
    staging: Staging,
    /// Workgroups in x and y: a 2D grid, as one dimension cannot hold a 1080p frame's rays.
    grid: (u32, u32),
}

/// Bytes of the tally: hits and checksum, one u32 each.
const TALLY_BYTES: u64 = 8;

impl IntersectRegisters {
    /// The pass over camera rays 0..`rays` of a frame of `pixels` pixels (sample i at pixel
    /// i % pixels, as generate numbers a share's path samples), on `scene`'s bindings.
    pub fn new(
        ctx: &GpuContext,
        scene: &SceneBuffers,
        rays: u32,
        pixels: u32,
        workgroup_size: u32,
        checks: ShaderChecks,
    ) -> Result<Self> {
        ctx.check_workgroup_size(workgroup_size)?;
        let max = ctx.summary.max_compute_workgroups_per_dimension;
        let groups = rays.div_ceil(workgroup_size).max(1);
        let x = groups.min(max);
        let y = groups.div_ceil(x);
        if y > max {
            bail!("{rays} camera rays need {groups} workgroups of {workgroup_size}: more than {max} x {max}");
        }
        let module = ctx.shader(label::INTERSECT_REGISTERS, shaders::INTERSECT_REGISTERS, checks)?;
        let layout = ctx.bind_group_layout(
            label::INTERSECT_REGISTERS,
            &[uniform_entry(0, false), storage_entry(1, false)],
        );
        let layouts = [&scene.layout, &layout];
        let constants = scene.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        let pipeline =
            ctx.stages.pipeline(label::INTERSECT_REGISTERS, &module, &layouts, &constants, || {
                ctx.compute_pipeline(label::INTERSECT_REGISTERS, &module, &layouts, &constants)
            })?;
        let params = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera rays"),
            contents: bytemuck::cast_slice(&[rays, pixels, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let tally = storage_zeroed(
            ctx,
            "intersect_registers tally",
            TALLY_BYTES,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        )?;
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label::INTERSECT_REGISTERS),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: tally.as_entire_binding() },
            ],
        });
        ctx.check()?;
        Ok(Self {
            pipeline,
            group,
            tally,
            staging: Staging::new(ctx, "intersect_registers tally read-back", TALLY_BYTES),
            grid: (x, y),
        })
    }

    /// Traces every camera ray once in one dispatch, timed by `timer` under its label (its own
    /// submission, waited for), and returns the tally.
    pub fn trace(&self, ctx: &GpuContext, scene: &SceneBuffers, timer: &mut GpuTimer) -> Result<Tally> {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.tally, 0, None);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label::INTERSECT_REGISTERS),
                timestamp_writes: timer.pass(label::INTERSECT_REGISTERS),
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &scene.bind_group, &[]);
            pass.set_bind_group(1, &self.group, &[]);
            pass.dispatch_workgroups(self.grid.0, self.grid.1, 1);
        }
        timer.submit_batch(ctx, encoder)?;
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.staging.copy(&mut encoder, &self.tally, TALLY_BYTES);
        ctx.queue.submit([encoder.finish()]);
        let words: Vec<u32> = self.staging.read(ctx, TALLY_BYTES)?;
        Ok(Tally { hits: words[0] as u64, checksum: words[1] })
    }
}
