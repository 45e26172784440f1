//! The ray sort (`--ray-sort`, `shaders/wavefront/ray_sort.wgsl`, issue 26's third remedy):
//! before each intersect, a counting sort orders the ray queue by a key of each ray (its
//! direction's octant, and with `octant-cell` also its origin's cell in a 4×4×4 grid over the
//! scene's bounds, in Morton order), as Garanzha & Loop sort rays, so that a subgroup's lanes
//! traverse the same part of the BVH. Material order needs no sort here: per-material shade
//! queues are it. Three passes (count, one-workgroup scan, scatter) over the queue, sized by
//! intersect's own arguments; the queue's copy and keys wait in the material queues' regions,
//! which are empty until intersect fills them, so the sort needs 4 KiB of new memory.

use super::super::buffers::{storage_entry, storage_zeroed};
use super::super::context::GpuContext;
use super::super::memory::{MemoryCategory, MemoryLedger};
use crate::options::RaySort;
use anyhow::Result;

/// Keys the shader's buckets hold (`KEYS` in WGSL).
const KEYS: u64 = 512;

impl RaySort {
    /// The `CELL_BITS` pipeline constant: origin-cell bits per axis in the key.
    pub fn cell_bits(self) -> u32 {
        match self {
            RaySort::OctantCell => 2,
            _ => 0,
        }
    }
}

/// The ray sort's buckets and their bind group (group 2 of its passes): counts, then each key's
/// next position, zeroed once (the scan clears the counts).
pub(super) fn buckets(
    ctx: &GpuContext,
    memory: &mut MemoryLedger,
) -> Result<(wgpu::BindGroupLayout, wgpu::BindGroup)> {
    let buckets = memory.track(
        MemoryCategory::Queues,
        storage_zeroed(ctx, "ray sort buckets", 2 * KEYS * 4, wgpu::BufferUsages::empty())?,
    );
    let layout = ctx.bind_group_layout("ray sort", &[storage_entry(0, false)]);
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("ray sort"),
        layout: &layout,
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: buckets.as_entire_binding() }],
    });
    Ok((layout, group))
}

use super::pass::{Binds, Constants, Launch, Pass, Phase, Queue, Shader};
use super::path_state::ARGS_INTERSECT;
use crate::gpu::label;

/// Count, scan (one workgroup), scatter over the ray queue, before intersect.
pub(super) fn passes(cell_bits: u32, c: &Constants) -> Vec<Pass> {
    let pass = |l, launch| {
        Pass::new(l, Phase::Iteration, Shader::RaySort, launch, Binds::RaySort)
            .with(&[c.workgroup, ("CELL_BITS", cell_bits as f64)])
            .scene()
            .queues(&[Queue::Rays], &[Queue::Rays])
    };
    vec![
        pass(label::RAY_SORT_COUNT, Launch::Indirect(ARGS_INTERSECT)),
        pass(label::RAY_SORT_SCAN, Launch::Direct(1)),
        pass(label::RAY_SORT_SCATTER, Launch::Indirect(ARGS_INTERSECT)),
    ]
}
