//! The experiment's GPU: opened when the first GPU run needs it, and opened afresh after a run
//! fails on the GPU, because a lost or errored device cannot be trusted with the next run.

use anyhow::Result;

use crate::gpu::context::AdapterSummary;
use crate::gpu::GpuContext;

pub struct GpuSlot {
    filter: Option<String>,
    ctx: Option<GpuContext>,
    /// The adapter of the last context opened.
    pub adapter: Option<AdapterSummary>,
}

impl GpuSlot {
    pub fn new(filter: Option<String>) -> Self {
        Self { filter, ctx: None, adapter: None }
    }

    pub fn get(&mut self) -> Result<&GpuContext> {
        if self.ctx.is_none() {
            let ctx = GpuContext::new(self.filter.as_deref())?;
            self.adapter = Some(ctx.summary.clone());
            self.ctx = Some(ctx);
        }
        Ok(self.ctx.as_ref().expect("opened above"))
    }

    /// Drops the context; the next [`GpuSlot::get`] opens a new device.
    pub fn reset(&mut self) {
        self.ctx = None;
    }
}
