//! compact_states (`shaders/wavefront/compact_states.wgsl`, `--compact-states on`): before each
//! refill, the live paths above the live count move into the free slots below it, so the
//! refill's consecutive samples take the contiguous slots from the live count on. Three passes,
//! sized on the GPU (queue_setup_regenerate sizes the first; they dispatch nothing on iterations
//! that do not refill).

use super::super::stage::{Stage, Workgroups};
use super::super::{context::GpuContext, label, shaders};
use super::path_state::{ARGS_COMPACT_STATES_FIND, ARGS_COMPACT_STATES_MOVE};
use super::queue_setup::QueueSetup;
use super::{Bindings, WaveRecorder};
use anyhow::Result;

pub struct CompactStatesPasses {
    find: Stage,
    r#move: Stage,
}

impl CompactStatesPasses {
    pub fn new(ctx: &GpuContext, b: &Bindings, workgroup_size: u32) -> Result<Self> {
        let module = ctx.shader(label::COMPACT_STATES_FIND, shaders::COMPACT_STATES, b.shader_checks)?;
        let constants = b.constants(&[("WORKGROUP_SIZE", workgroup_size as f64)]);
        // Scene and path state only: no instrument counters.
        let layouts = &b.layouts()[..2];
        let stage = |l| Stage::new(ctx, l, &module, layouts, &constants);
        Ok(Self { find: stage(label::COMPACT_STATES_FIND)?, r#move: stage(label::COMPACT_STATES_MOVE)? })
    }

    /// The passes between queue_setup_regenerate and the refill of iteration `i`.
    pub fn record(&self, wave: &mut WaveRecorder<'_>, setup: &QueueSetup, i: u32) {
        let find = Workgroups::Indirect(&wave.b.state.indirect, ARGS_COMPACT_STATES_FIND * 12);
        wave.record(&self.find, Some(i), 2, find);
        setup.record_compact_states(wave, i);
        let r#move = Workgroups::Indirect(&wave.b.state.indirect, ARGS_COMPACT_STATES_MOVE * 12);
        wave.record(&self.r#move, Some(i), 2, r#move);
    }
}
