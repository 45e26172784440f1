//! slot_sweep (`shaders/wavefront/slot_sweep.wgsl`): slot order's queues with the atomic
//! compaction method. One pass over the pool's slots after shade appends each to the next ray
//! queue, the free list (regenerate) or the shadow queue; appends aggregated per subgroup keep
//! each subgroup's slots together in ascending order, so later passes read as few lines of path
//! state as in the scan's exact slot order (though not as one ascending stream), without the
//! scan's three passes and their barriers. Sized on the GPU by queue_setup_shade (the scan's arguments: every slot).

use super::super::shaders::{self, Hook};
use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label};
use super::path_state::ARGS_COMPACT;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct SlotSweep {
    stage: Stage,
}

impl SlotSweep {
    pub fn new(ctx: &GpuContext, b: &Bindings) -> Result<Self> {
        let source = shaders::SLOT_SWEEP.select(&[(Hook::AppendSubgroup, b.subgroup_append)]);
        let module = ctx.shader(label::SLOT_SWEEP, source, b.shader_checks)?;
        // Scene and path state only: no instrument counters.
        let layouts = &b.layouts()[..2];
        let constants = b.schedule_constants();
        Ok(Self { stage: Stage::new(ctx, label::SLOT_SWEEP, &module, layouts, &constants)? })
    }

    pub fn record(&self, wave: &mut WaveRecorder<'_>, bounce: u32) {
        let args = Workgroups::Indirect(&wave.b.state.indirect, ARGS_COMPACT * 12);
        wave.record(&self.stage, Some(bounce), 2, args);
    }
}
