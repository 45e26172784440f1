// The `--instrument` variant: counts, per pass slot, the subgroup lanes active at the call
// (subgroupAdd over active lanes), the subgroups that arrived and the lanes they had (each
// subgroup's own `subgroup_size`, which the entry point hands to `instrument_begin`), so the
// efficiency is right whatever width the driver chose for this pipeline (AMD's wave32 or wave64,
// Apple's 32 where wgpu reports 4..64). Counters are 64-bit (two words, low first): a frame at
// 1080p and thousands of spp passes 2^32 active lanes. The portable counterpart of a
// profiler's warp execution efficiency.

#include "shared/instrument_ids.wgsl"

@group(2) @binding(0) var<storage, read_write> simd_counters: array<atomic<u32>>;

// Words per slot: active lanes, subgroups, available lanes; each a (low, high) pair.
const SIMD_SLOT_WORDS: u32 = 6u;

// This invocation's subgroup width, set once at the top of each instrumented entry point.
var<private> subgroup_width: u32 = 0u;

// The traversal the next BVH steps belong to (its first slot), set by the caller before each
// closest_hit / occluder, since one traversal loop serves every pass.
var<private> traversal_slot: u32 = 0u;

fn instrument_traversal(first_slot: u32) {
    traversal_slot = first_slot;
}

// One traversal step of kind TRAVERSE_*: called inside the loop, once per iteration per lane.
fn instrument_step(kind: u32) {
    instrument(traversal_slot + kind);
}

fn instrument_begin(width: u32) {
    subgroup_width = width;
}

// Adds `x` to the 64-bit counter at word `i`: the addition that carries the low word over adds
// one to the high word.
fn add64(i: u32, x: u32) {
    let old = atomicAdd(&simd_counters[i], x);
    if old > 0xffffffffu - x {
        atomicAdd(&simd_counters[i + 1u], 1u);
    }
}

fn instrument(pass_id: u32) {
    let lanes = subgroupAdd(1u);
    // The first active lane (exclusive prefix 0) records for the whole subgroup.
    if subgroupExclusiveAdd(1u) == 0u {
        let base = SIMD_SLOT_WORDS * pass_id;
        add64(base, lanes);
        add64(base + 2u, 1u);
        add64(base + 4u, subgroup_width);
    }
}
