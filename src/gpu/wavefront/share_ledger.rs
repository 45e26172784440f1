//! The waves' per-share counters, copied on the GPU into a ledger rather than read back after
//! each share (issue 42): the host records and submits share after share without waiting for
//! any of them, and reads the ledger once, after the frame's last submission (or when it
//! fills). Before, each share ended with the host waiting for the GPU and reading its counters
//! back twice, the GPU idle meanwhile and while the next share was recorded.

use anyhow::Result;

use super::super::buffers::read_back;
use super::super::context::GpuContext;
use super::super::memory::{MemoryCategory, MemoryLedger};
use super::path_state::{schedule_word as word, PathState, COUNTER_SCHEDULE, COUNTER_STATS, QUEUE_COUNT};
use super::schedule::{clear_share_counters, ScheduleStats};
use super::QueueHistogram;

/// Shares the ledger holds before the host must read it (a wait inside the frame): more than
/// any job of the committed configs has (1920x1080x64 on the default pool: 64 shares).
pub const SLOTS: u64 = 512;

/// What the host knows of a share when it records it; the GPU's counters complete it.
#[derive(Clone, Copy, Debug)]
pub struct ShareWork {
    pub units: u32,
    pub iterations: u32,
    pub dispatches: u64,
}

/// Per share: the histogram rows (`stats_bounces` × `QUEUE_COUNT` words from `COUNTER_STATS`),
/// then the scheduling words (from `COUNTER_SCHEDULE`).
pub struct ShareLedger {
    buffer: wgpu::Buffer,
    rows: u64,
    pending: Vec<ShareWork>,
}

impl ShareLedger {
    pub fn new(ctx: &GpuContext, state: &PathState, memory: &mut MemoryLedger) -> Self {
        let rows = state.stats_bounces as u64 * QUEUE_COUNT;
        let size = SLOTS * (rows + word::WORDS) * 4;
        memory.add(MemoryCategory::Counters, size);
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("share ledger"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Self { buffer, rows, pending: Vec::new() }
    }

    fn stride(&self) -> u64 {
        (self.rows + word::WORDS) * 4
    }

    /// Records, after a share's passes, the copy of its counters into the next slot and their
    /// clearing for the next share.
    pub fn record(&mut self, enc: &mut wgpu::CommandEncoder, state: &PathState, work: ShareWork) {
        assert!(!self.is_full(), "drain the share ledger before recording more");
        let at = self.pending.len() as u64 * self.stride();
        let stats = COUNTER_STATS * 4;
        enc.copy_buffer_to_buffer(&state.counters, stats, &self.buffer, at, self.rows * 4);
        let schedule = COUNTER_SCHEDULE * 4;
        enc.copy_buffer_to_buffer(
            &state.counters,
            schedule,
            &self.buffer,
            at + self.rows * 4,
            word::WORDS * 4,
        );
        enc.clear_buffer(&state.counters, stats, Some(self.rows * 4));
        clear_share_counters(enc, state);
        self.pending.push(work);
    }

    pub fn is_full(&self) -> bool {
        self.pending.len() as u64 >= SLOTS
    }

    /// Reads the recorded shares back (the host has waited for them) into `stats` and
    /// `histogram`, in order, and empties the ledger.
    pub fn drain(
        &mut self,
        ctx: &GpuContext,
        stats: &mut ScheduleStats,
        mut histogram: Option<&mut QueueHistogram>,
    ) -> Result<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let size = self.pending.len() as u64 * self.stride();
        let words: Vec<u32> = read_back(ctx, &self.buffer, size)?;
        let (stride, rows) = ((self.stride() / 4) as usize, self.rows as usize);
        for (slot, work) in words.chunks_exact(stride).zip(std::mem::take(&mut self.pending)) {
            stats.add_share_words(ctx, &slot[rows..], work.units, work.iterations, work.dispatches)?;
            stats.add_rows(&slot[..rows]);
            if let Some(h) = histogram.as_deref_mut() {
                super::add_histogram_rows(h, &slot[..rows], rows / QUEUE_COUNT as usize);
            }
        }
        Ok(())
    }
}
