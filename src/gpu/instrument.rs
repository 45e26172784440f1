//! SIMD efficiency (`--instrument`): per pass slot, subgroup lanes active at the instrumented
//! point over lanes available (subgroups arriving × subgroup size). Shaders write the counters
//! in their `.instrumented` variants (`shaders/shared/instrument_on.wgsl`); timing runs use the
//! plain variants and carry no counters.

use super::buffers::{read_back, storage_entry, storage_zeroed};
use super::context::GpuContext;
use super::memory::{MemoryCategory, MemoryLedger};
use anyhow::{bail, Result};
use std::collections::BTreeMap;

/// Slot names, in the order of `shaders/shared/instrument_ids.wgsl`.
pub const SLOTS: [&str; 15] = [
    "megakernel_bounce",
    "megakernel_material",
    "megakernel_lambertian",
    "megakernel_metal",
    "megakernel_dielectric",
    "megakernel_emissive",
    "generate",
    "intersect",
    "shade_lambertian",
    "shade_metal",
    "shade_dielectric",
    "shade_emissive",
    "shade",
    "megakernel_shadow",
    "shadow",
];

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimdEfficiency {
    /// Active lanes / available lanes, in [0, 1].
    pub efficiency: f64,
    /// Subgroups that reached the point.
    pub subgroups: u64,
}

pub struct SimdCounters {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    buffer: wgpu::Buffer,
}

impl SimdCounters {
    pub fn new(ctx: &GpuContext, memory: &mut MemoryLedger) -> Result<Self> {
        if !ctx.summary.subgroups {
            bail!(
                "--instrument counts lanes with subgroup operations, which {} does not offer",
                ctx.summary.name
            );
        }
        if ctx.summary.subgroup_min_size != ctx.summary.subgroup_max_size {
            log::warn!(
                "subgroup size varies ({}..={}) on {}: efficiencies assume {}",
                ctx.summary.subgroup_min_size,
                ctx.summary.subgroup_max_size,
                ctx.summary.name,
                ctx.summary.subgroup_max_size
            );
        }
        let buffer = memory.track(
            MemoryCategory::Instrumentation,
            storage_zeroed(ctx, "simd counters", SLOTS.len() as u64 * 8, wgpu::BufferUsages::COPY_SRC)?,
        );
        let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("simd counters"),
            entries: &[storage_entry(0, false)],
        });
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("simd counters"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        Ok(Self { layout, bind_group, buffer })
    }

    /// Efficiency of every slot that was reached.
    pub fn read(&self, ctx: &GpuContext) -> Result<BTreeMap<String, SimdEfficiency>> {
        let raw: Vec<u32> = read_back(ctx, &self.buffer, SLOTS.len() as u64 * 8)?;
        let size = ctx.summary.subgroup_max_size.max(1) as f64;
        Ok(SLOTS
            .iter()
            .enumerate()
            .filter(|&(i, _)| raw[2 * i + 1] > 0)
            .map(|(i, name)| {
                let (lanes, groups) = (raw[2 * i] as f64, raw[2 * i + 1] as u64);
                (
                    name.to_string(),
                    SimdEfficiency { efficiency: lanes / (groups as f64 * size), subgroups: groups },
                )
            })
            .collect())
    }
}
