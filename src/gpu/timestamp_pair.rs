//! Two timestamps around a stretch of GPU work, for the microbenchmarks (`dispatch-cost`,
//! `bandwidth`): written by the compute passes that begin and end the stretch, resolved at the
//! end of its encoder and read back in a submission of their own (wgpu #6406: resolved and
//! copied in one encoder they can read as zeros on Vulkan). Renders time their passes with
//! [`super::timing::GpuTimer`] instead.

use anyhow::Result;

use super::buffers::Staging;
use super::context::GpuContext;

/// The stretch's first timestamp.
pub const START: u32 = 0;
/// The stretch's last timestamp.
pub const END: u32 = 1;

pub struct TimestampPair {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: Staging,
}

impl TimestampPair {
    /// The pair, or `None` on an adapter without timestamps.
    pub fn new(ctx: &GpuContext, label: &'static str) -> Option<Self> {
        ctx.summary.timestamps.then(|| Self {
            set: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            staging: Staging::new(ctx, label, 16),
        })
    }

    /// A compute pass's writes: at its beginning and at its end, each `None` or the timestamp it
    /// writes there ([`START`], the stretch's first; [`END`], its last); `None` for neither.
    pub fn writes(
        &self,
        beginning: Option<u32>,
        end: Option<u32>,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        (beginning.is_some() || end.is_some()).then_some(wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: beginning,
            end_of_pass_write_index: end,
        })
    }

    /// Records the resolve of both timestamps, as the encoder's last command.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..2, &self.resolve, 0);
    }

    /// Seconds between the two, once the work has run; `None` where they did not advance (an
    /// adapter that claims timestamps and writes zeros).
    pub fn seconds(&self, ctx: &GpuContext) -> Result<Option<f64>> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        self.staging.copy(&mut enc, &self.resolve, 16);
        ctx.queue.submit([enc.finish()]);
        let ticks: Vec<u64> = self.staging.read(ctx, 16)?;
        let ns = ctx.queue.get_timestamp_period() as f64;
        Ok((ticks[1] > ticks[0]).then(|| (ticks[1] - ticks[0]) as f64 * ns * 1e-9))
    }
}
