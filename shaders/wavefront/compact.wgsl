// compact: builds dense queues by a stable prefix-sum scan (the `scan` compaction method) over
// the queue positions the previous pass processed (COUNTER_POSITIONS, dispatched indirectly), from
// the queue each position asked for in `next_queue`: cost follows the live paths, not the pool. Three passes: per-workgroup scan,
// scan of the workgroup totals, scatter. Lanes of a vec4 count up to four queues at once (the
// material queues after intersect; lane 0 = the next ray queue after shade).
// Rust side: src/gpu/wavefront/compact.rs.

#include "shared/path_state.wgsl"

const SCAN_WG: u32 = 256u;
// false: building the material queues (after intersect); true: the next ray queue (after shade).
override TARGET_RAYS: bool = false;

var<workgroup> scratch: array<vec4<u32>, SCAN_WG>;

fn one_hot(q: u32) -> vec4<u32> {
    if q == DEAD {
        return vec4<u32>(0u);
    }
    return vec4<u32>(vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(lane_of(q)));
}

fn lane_of(q: u32) -> u32 {
    return select(q - QUEUE_MATERIAL_0, 0u, q < QUEUE_MATERIAL_0);
}

// Inclusive Hillis–Steele scan of `scratch` across the workgroup.
fn scan_workgroup(lid: u32) {
    for (var step = 1u; step < SCAN_WG; step <<= 1u) {
        workgroupBarrier();
        var v = scratch[lid];
        if lid >= step {
            v += scratch[lid - step];
        }
        workgroupBarrier();
        scratch[lid] = v;
    }
    workgroupBarrier();
}

@compute @workgroup_size(SCAN_WG)
fn compact_scan(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32,
                @builtin(workgroup_id) wid: vec3<u32>) {
    let p = gid.x;
    var q = DEAD;
    if p < atomicLoad(&counters[COUNTER_POSITIONS]) {
        q = next_queue[p];
    }
    let v = one_hot(q);
    scratch[lid] = v;
    scan_workgroup(lid);
    if q != DEAD {
        scan_offset[p] = (scratch[lid] - v)[lane_of(q)];
    }
    if lid == SCAN_WG - 1u {
        block_sums[wid.x] = scratch[lid];
    }
}

// One workgroup: exclusive scan of the block totals, in chunks; writes the queue counts.
var<workgroup> positions: u32;

@compute @workgroup_size(SCAN_WG)
fn compact_blocks(@builtin(local_invocation_index) lid: u32) {
    if lid == 0u {
        positions = atomicLoad(&counters[COUNTER_POSITIONS]);
    }
    let blocks = (workgroupUniformLoad(&positions) + SCAN_WG - 1u) / SCAN_WG;
    var running = vec4<u32>(0u);
    for (var base = 0u; base < blocks; base += SCAN_WG) {
        let i = base + lid;
        var v = vec4<u32>(0u);
        if i < blocks {
            v = block_sums[i];
        }
        scratch[lid] = v;
        scan_workgroup(lid);
        if i < blocks {
            block_sums[i] = running + scratch[lid] - v;
        }
        running += scratch[SCAN_WG - 1u];
    }
    if lid == 0u {
        let bounce = current_bounce();
        if TARGET_RAYS {
            atomicStore(&counters[QUEUE_RAY_0 + (bounce + 1u) % 2u], running.x);
        } else {
            for (var k = 0u; k < 4u; k++) {
                atomicStore(&counters[QUEUE_MATERIAL_0 + k], running[k]);
            }
        }
    }
}

@compute @workgroup_size(SCAN_WG)
fn compact_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let p = gid.x;
    if p >= atomicLoad(&counters[COUNTER_POSITIONS]) {
        return;
    }
    let q = next_queue[p];
    if q == DEAD {
        return;
    }
    queues[q * wave.pool + block_sums[wid.x][lane_of(q)] + scan_offset[p]] = scan_slot[p];
}
