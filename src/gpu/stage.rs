//! A GPU stage: one labelled compute pipeline and how to record it (vello's thin recording layer).
//! The label names the pipeline, the WGSL entry point, the timestamp slot and the report key.

use super::context::GpuContext;
use super::timing::GpuTimer;
use anyhow::Result;

/// How many workgroups a recorded pass launches.
pub enum Workgroups<'a> {
    Direct(u32),
    /// Read from `buffer` at `offset` (written on the GPU by a setup pass).
    Indirect(&'a wgpu::Buffer, u64),
}

pub struct Stage {
    pub label: &'static str,
    pipeline: wgpu::ComputePipeline,
}

impl Stage {
    /// The pipeline for entry point `label` of `module`: built on the first render that needs it,
    /// reused from the device's [`StageCache`](super::stage_cache::StageCache) after.
    pub fn new(
        ctx: &GpuContext,
        label: &'static str,
        module: &wgpu::ShaderModule,
        layouts: &[&wgpu::BindGroupLayout],
        constants: &[(&str, f64)],
    ) -> Result<Self> {
        let pipeline = ctx.stages.pipeline(label, module, layouts, constants, || {
            ctx.compute_pipeline(label, module, layouts, constants)
        })?;
        Ok(Self { label, pipeline })
    }

    /// Records the stage as its own timed compute pass. `groups[i]` binds group i with its
    /// dynamic offsets.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        bounce: Option<u32>,
        groups: &[(&wgpu::BindGroup, Vec<u32>)],
        workgroups: Workgroups<'_>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: timer.pass_at(self.label, bounce),
        });
        self.dispatch(&mut pass, groups, workgroups);
    }

    /// Records the stage's dispatch into an open compute pass (shared with other dispatches:
    /// `--compute-passes shared`; the caller counts it with the timer).
    pub fn dispatch(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &[(&wgpu::BindGroup, Vec<u32>)],
        workgroups: Workgroups<'_>,
    ) {
        pass.set_pipeline(&self.pipeline);
        for (i, (group, offsets)) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, *group, offsets);
        }
        match workgroups {
            Workgroups::Direct(x) => pass.dispatch_workgroups(x, 1, 1),
            Workgroups::Indirect(buffer, offset) => pass.dispatch_workgroups_indirect(buffer, offset),
        }
    }
}
