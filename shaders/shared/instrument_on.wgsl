// The `--instrument` variant: counts, per pass slot, how many subgroup lanes are active at the
// call (subgroupAdd over active lanes) and how many subgroups arrived; the host divides by the
// subgroup size. The portable counterpart of a profiler's warp execution efficiency.

#include "shared/instrument_ids.wgsl"

@group(2) @binding(0) var<storage, read_write> simd_counters: array<atomic<u32>>;

fn instrument(pass_id: u32) {
    let lanes = subgroupAdd(1u);
    // The first active lane (exclusive prefix 0) records for the whole subgroup.
    if subgroupExclusiveAdd(1u) == 0u {
        atomicAdd(&simd_counters[2u * pass_id], lanes);
        atomicAdd(&simd_counters[2u * pass_id + 1u], 1u);
    }
}
