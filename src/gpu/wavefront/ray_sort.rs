//! The ray sort (`--ray-sort`, `shaders/wavefront/ray_sort.wgsl`, issue 26's third remedy):
//! before each intersect, a counting sort orders the ray queue by a key of each ray (its
//! direction's octant, and with `octant-cell` also its origin's cell in a 4×4×4 grid over the
//! scene's bounds, in Morton order), as Garanzha & Loop sort rays, so that a subgroup's lanes
//! traverse the same part of the BVH. Material order needs no sort here: per-material shade
//! queues are it. Three passes (count, one-workgroup scan, scatter) over the queue, sized by
//! intersect's own arguments; the queue's copy and keys wait in the material queues' regions,
//! which are empty until intersect fills them, so the sort needs 4 KiB of new memory.

use super::super::buffers::{storage_entry, storage_zeroed};
use super::super::memory::{MemoryCategory, MemoryLedger};
use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::ARGS_INTERSECT;
use super::{Bindings, WaveRecorder};
use crate::options::RaySort;
use anyhow::Result;

/// Keys the shader's buckets hold (`KEYS` in WGSL).
const KEYS: u64 = 512;

impl RaySort {
    /// The `CELL_BITS` pipeline constant: origin-cell bits per axis in the key.
    fn cell_bits(self) -> u32 {
        match self {
            RaySort::OctantCell => 2,
            _ => 0,
        }
    }
}

pub struct RaySortPasses {
    count: Stage,
    scan: Stage,
    scatter: Stage,
    group: wgpu::BindGroup,
}

impl RaySortPasses {
    pub fn new(
        ctx: &GpuContext,
        b: &Bindings,
        workgroup_size: u32,
        sort: RaySort,
        memory: &mut MemoryLedger,
    ) -> Result<Self> {
        let module = ctx.shader(label::RAY_SORT_COUNT, shaders::RAY_SORT, b.shader_checks)?;
        let constants =
            b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64), ("CELL_BITS", sort.cell_bits() as f64)]);
        // Counts, then each key's next position: zeroed once, and the scan clears the counts.
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
        // Scene, path state and the buckets (never the instrument counters).
        let layouts = [b.layouts()[0], b.layouts()[1], &layout];
        let stage = |l| Stage::new(ctx, l, &module, &layouts, &constants);
        Ok(Self {
            count: stage(label::RAY_SORT_COUNT)?,
            scan: stage(label::RAY_SORT_SCAN)?,
            scatter: stage(label::RAY_SORT_SCATTER)?,
            group,
        })
    }

    /// The passes between queue_setup_intersect and intersect of iteration `i`.
    pub fn record(&self, wave: &mut WaveRecorder<'_>, i: u32) {
        let indirect = &wave.b.state.indirect;
        let over_queue = || Workgroups::Indirect(indirect, ARGS_INTERSECT * 12);
        let group = || Some((&self.group, vec![]));
        wave.record_with(&self.count, Some(i), 2, group(), over_queue());
        wave.record_with(&self.scan, Some(i), 2, group(), Workgroups::Direct(1));
        wave.record_with(&self.scatter, Some(i), 2, group(), over_queue());
    }
}
