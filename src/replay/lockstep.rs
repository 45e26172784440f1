//! Lockstep execution of a subgroup's lanes at width W, counting the device's instrument slots:
//! at each instrumented block, the lanes that run it; a block no lane runs is not issued.

use super::recorder::{is_step, INNER};
use crate::gpu::instrument::{self, SimdEfficiency, SLOTS};
use anyhow::Result;
use std::collections::BTreeMap;

/// Per slot (instrument.rs order): active lanes, subgroup-iterations issued, lanes available.
#[derive(Clone, Debug, Default)]
pub struct SlotCounts {
    pub slots: Vec<[u64; 3]>,
}

impl SlotCounts {
    pub fn new() -> Self {
        Self { slots: vec![[0; 3]; SLOTS.len()] }
    }

    /// A block `slot` run by `lanes` of a `width`-lane subgroup (nothing issued for none).
    pub fn count(&mut self, slot: u32, lanes: usize, width: u32) {
        if lanes > 0 {
            let s = &mut self.slots[slot as usize];
            s[0] += lanes as u64;
            s[1] += 1;
            s[2] += u64::from(width);
        }
    }

    pub fn add(&mut self, other: &SlotCounts) {
        for (a, b) in self.slots.iter_mut().zip(&other.slots) {
            for k in 0..3 {
                a[k] += b[k];
            }
        }
    }

    /// The counts of a whole frame estimated from two nested prefixes of it, each replayed as a
    /// job of its own (the regenerating methods' subset): `short`'s counts plus `f` times what
    /// `long` adds to them. Both jobs start alike and drain alike, so the difference is the
    /// steady state's cost of the samples `long` adds, with start and drain cancelled; `f` is
    /// the frame's samples beyond `short`'s over that difference's.
    pub fn extrapolate(short: &SlotCounts, long: &SlotCounts, f: f64) -> SlotCounts {
        let slots = short
            .slots
            .iter()
            .zip(&long.slots)
            .map(|(a, b)| {
                let [lanes, groups, available] = std::array::from_fn(|k| extrapolate(a[k], b[k], f));
                // An estimate: the active lanes can come out a little above those available
                // where a slot runs nearly full, and a slot no subgroup reaches has none.
                if groups == 0 || available == 0 {
                    [0; 3]
                } else {
                    [lanes.min(available), groups, available]
                }
            })
            .collect();
        SlotCounts { slots }
    }

    /// The figures the device reports, under the same keys: entry points, traversal steps,
    /// `work:<pass>` and the frame's `warp_execution_efficiency`.
    pub fn efficiencies(&self) -> Result<BTreeMap<String, SimdEfficiency>> {
        let mut raw = Vec::with_capacity(SLOTS.len() * 6);
        for s in &self.slots {
            for v in s {
                raw.extend([*v as u32, (*v >> 32) as u32]);
            }
        }
        let mut out = instrument::decode(&raw)?;
        out.extend(instrument::work_weighted(&raw));
        Ok(out)
    }
}

/// `short + f × (long − short)`, rounded, at least 0 (see [`SlotCounts::extrapolate`]).
pub fn extrapolate(short: u64, long: u64, f: f64) -> u64 {
    (short as f64 + f * (long as f64 - short as f64)).round().max(0.0) as u64
}

/// One lane: its events and how far the replay has run them.
pub struct Lane<'a> {
    pub events: &'a [u32],
    pub at: usize,
}

impl Lane<'_> {
    pub fn next(&self) -> Option<u32> {
        self.events.get(self.at).copied()
    }
}

/// Runs the traversal that `lanes` (indices into `all`, each at its traversal's first step) take
/// in lockstep: iteration j runs the inner block for lanes at an inner node, the leaf block and
/// its primitive loop for lanes at a leaf; a lane leaves the loop after its last step. `first`:
/// the traversal's first slot (PASS_*_TRAVERSE).
pub fn traverse(all: &mut [Lane], lanes: &[usize], first: u32, width: u32, counts: &mut SlotCounts) {
    let mut running: Vec<usize> = lanes.to_vec();
    while !running.is_empty() {
        let (mut inner, mut leaf) = (0, 0);
        let mut positions = [0usize; 24];
        running.retain(|&l| {
            let lane = &mut all[l];
            match lane.next().filter(|&e| is_step(e)) {
                Some(INNER) => inner += 1,
                Some(mask) => {
                    leaf += 1;
                    for (p, n) in positions.iter_mut().enumerate() {
                        *n += (mask >> p & 1) as usize;
                    }
                }
                None => return false,
            }
            lane.at += 1;
            true
        });
        counts.count(first, inner, width);
        counts.count(first + 1, leaf, width);
        for n in positions {
            counts.count(first + 2, n, width);
        }
    }
}

/// The index of the slot called `name` (a name of `instrument::SLOTS`).
pub fn slot(name: &str) -> u32 {
    SLOTS.iter().position(|s| *s == name).unwrap_or_else(|| panic!("no SIMD slot {name}")) as u32
}
