//! The experiment's GPU: opened when the first GPU run needs it, and opened afresh after a run
//! fails on the GPU, because a lost or errored device cannot be trusted with the next run. Beside
//! it, NVML on the same device where there is one, to read its clocks and temperature.

use anyhow::Result;

use crate::gpu::context::AdapterSummary;
use crate::gpu::state::{GpuMonitor, GpuState};
use crate::gpu::GpuContext;

pub struct GpuSlot {
    filter: Option<String>,
    ctx: Option<GpuContext>,
    /// The adapter of the last context opened.
    pub adapter: Option<AdapterSummary>,
    /// NVML on the adapter's device (opened with the first context; None where unavailable).
    monitor: Option<GpuMonitor>,
    monitor_tried: bool,
}

impl GpuSlot {
    pub fn new(filter: Option<String>) -> Self {
        Self { filter, ctx: None, adapter: None, monitor: None, monitor_tried: false }
    }

    pub fn get(&mut self) -> Result<&GpuContext> {
        if self.ctx.is_none() {
            let ctx = GpuContext::new(self.filter.as_deref())?;
            if !self.monitor_tried {
                self.monitor = GpuMonitor::open(&ctx.summary);
                self.monitor_tried = true;
            }
            self.adapter = Some(ctx.summary.clone());
            self.ctx = Some(ctx);
        }
        Ok(self.ctx.as_ref().expect("opened above"))
    }

    /// Drops the context; the next [`GpuSlot::get`] opens a new device.
    pub fn reset(&mut self) {
        self.ctx = None;
    }

    /// The GPU's state now, where NVML reads it.
    pub fn sample(&self) -> Option<GpuState> {
        self.monitor.as_ref().map(GpuMonitor::sample)
    }

    /// Where [`GpuSlot::sample`] reads from, for the report (`NVML: NVIDIA H200`).
    pub fn state_source(&self) -> Option<String> {
        self.monitor.as_ref().map(|m| format!("NVML: {}", m.name))
    }
}
