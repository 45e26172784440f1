//! GPU memory as a cost: what each render allocated, by category, and the peak.
//!
//! The figures are the bytes the methods ask wgpu for (buffer and query-set sizes), not what
//! the driver reserves beyond them (alignment, internal allocations), which wgpu does not
//! expose. Every buffer a render creates lives until the render ends, so the resident total is
//! the sum of the categories; the peak adds the largest buffer that lives only during a
//! read-back (the film's staging copy).

use std::collections::BTreeMap;

/// What a buffer is for. The order is the report's column order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum MemoryCategory {
    /// Primitives, materials, BVH nodes, lights and the frame's constants.
    Scene,
    /// The image's per-pixel sums.
    Film,
    /// Per-sample radiance waiting for the accumulate pass.
    Samples,
    /// Per-path state of the wavefront's pool (rays, throughput, radiance, sample and bounce).
    PathState,
    /// The wavefront's ray and material queues, scan scratch and indirect dispatch arguments.
    Queues,
    /// The wavefront's shadow rays and their weights (`--nee on`).
    ShadowQueue,
    /// Atomic counters: queue lengths, statistics, the regenerating schedules' work counters.
    Counters,
    /// Per-dispatch uniform parameters.
    Parameters,
    /// Timestamp queries and SIMD-efficiency counters.
    Instrumentation,
}

impl MemoryCategory {
    pub const ALL: [MemoryCategory; 9] = [
        MemoryCategory::Scene,
        MemoryCategory::Film,
        MemoryCategory::Samples,
        MemoryCategory::PathState,
        MemoryCategory::Queues,
        MemoryCategory::ShadowQueue,
        MemoryCategory::Counters,
        MemoryCategory::Parameters,
        MemoryCategory::Instrumentation,
    ];

    /// The key in reports (report.json, runs.csv columns `memory_<key>`).
    pub fn key(self) -> &'static str {
        match self {
            MemoryCategory::Scene => "scene",
            MemoryCategory::Film => "film",
            MemoryCategory::Samples => "samples",
            MemoryCategory::PathState => "path_state",
            MemoryCategory::Queues => "queues",
            MemoryCategory::ShadowQueue => "shadow_queue",
            MemoryCategory::Counters => "counters",
            MemoryCategory::Parameters => "parameters",
            MemoryCategory::Instrumentation => "instrumentation",
        }
    }
}

/// A render's allocations, as they are made.
#[derive(Debug, Default)]
pub struct MemoryLedger {
    resident: BTreeMap<MemoryCategory, u64>,
    largest_transient: u64,
}

impl MemoryLedger {
    /// Counts `bytes` that live until the render ends.
    pub fn add(&mut self, category: MemoryCategory, bytes: u64) {
        *self.resident.entry(category).or_default() += bytes;
    }

    /// Counts `buffer` under `category` and hands it back: `let b = ledger.track(c, make()?);`.
    pub fn track(&mut self, category: MemoryCategory, buffer: wgpu::Buffer) -> wgpu::Buffer {
        self.add(category, buffer.size());
        buffer
    }

    /// Counts a buffer that lives only while other allocations stay (a read-back's staging copy).
    pub fn transient(&mut self, bytes: u64) {
        self.largest_transient = self.largest_transient.max(bytes);
    }

    pub fn summary(&self) -> GpuMemory {
        let by_category: BTreeMap<String, u64> =
            self.resident.iter().map(|(c, &b)| (c.key().to_owned(), b)).collect();
        let total: u64 = self.resident.values().sum();
        GpuMemory { by_category, total, peak: total + self.largest_transient }
    }
}

/// GPU memory of one render, in bytes.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct GpuMemory {
    /// Per category key ([`MemoryCategory::key`]); categories a method does not use are absent.
    pub by_category: BTreeMap<String, u64>,
    /// Every buffer the render holds until it ends.
    pub total: u64,
    /// The most held at once: `total` plus the largest read-back staging buffer.
    pub peak: u64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_sums_categories_and_peak_adds_the_largest_transient() {
        let mut m = MemoryLedger::default();
        m.add(MemoryCategory::Film, 100);
        m.add(MemoryCategory::Scene, 40);
        m.add(MemoryCategory::Film, 28);
        m.transient(100);
        m.transient(16);
        let s = m.summary();
        assert_eq!(s.by_category["film"], 128);
        assert_eq!(s.by_category["scene"], 40);
        assert!(!s.by_category.contains_key("queues"));
        assert_eq!(s.total, 168);
        assert_eq!(s.peak, 268);
    }

    #[test]
    fn keys_are_unique() {
        let keys: std::collections::BTreeSet<_> = MemoryCategory::ALL.iter().map(|c| c.key()).collect();
        assert_eq!(keys.len(), MemoryCategory::ALL.len());
    }
}
