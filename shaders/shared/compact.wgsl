// compact: builds dense queues by a stable prefix-sum scan (the `scan` compaction method) over
// the queue positions the previous pass processed (COUNTER_POSITIONS, dispatched indirectly), from
// the queue each position asked for in `next_queue`: cost follows the live paths, not the pool.
// Three passes: per-workgroup scan, scan of the workgroup totals (a workgroup per 1,024 of them),
// scatter. Lanes of a vec4 count up to four queues at once (the
// material queues after intersect; lane 0 = the next ray queue after shade).
// These are the passes' bodies: the entry files (wavefront/compact.wgsl, without subgroups, and
// wavefront/compact_subgroup.wgsl) each define `scan_workgroup(lid, lanes)`, an inclusive scan of
// `scratch`, include this, and wrap the bodies in entry points. Rust side: src/gpu/wavefront/compact.rs.

const SCAN_WG: u32 = 256u;
var<workgroup> scratch: array<vec4<u32>, SCAN_WG>;

// Where a lane sits in its subgroup (zeros for the workgroup scan, which needs no subgroups).
struct Lanes {
    lane: u32,
    size: u32,
    id: u32,
}

// false: building the material queues (after intersect); true: the next ray queue (after shade).
override TARGET_RAYS: bool = false;

fn one_hot(q: u32) -> vec4<u32> {
    if q == DEAD {
        return vec4<u32>(0u);
    }
    return vec4<u32>(vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(lane_of(q)));
}

fn lane_of(q: u32) -> u32 {
    return select(q - QUEUE_MATERIAL_0, 0u, q < QUEUE_MATERIAL_0);
}

fn compact_scan_main(gid: vec3<u32>, lid: u32, wid: vec3<u32>, lanes: Lanes) {
    let p = gid.x;
    var q = DEAD;
    if p < atomicLoad(&counters[COUNTER_POSITIONS]) {
        q = next_queue[p];
    }
    let v = one_hot(q);
    scratch[lid] = v;
    scan_workgroup(lid, lanes);
    if q != DEAD {
        scan_offset[p] = (scratch[lid] - v)[lane_of(q)];
    }
    if lid == SCAN_WG - 1u {
        block_sums[wid.x] = scratch[lid];
    }
}

// The block pass, spread over workgroups: workgroup g writes the exclusive prefix sums of the
// totals of its GROUP_CHUNKS·SCAN_WG blocks after the block totals (so no workgroup overwrites a
// total another still reads), starting from the sum of every block before its group, which it
// reduces itself. The group with the last block writes the queue counts. A single workgroup
// looping over every block total would leave all but one of a GPU's multiprocessors idle on a
// big pool; GROUP_CHUNKS chunks a workgroup keeps pools of up to 262,144 slots in one workgroup,
// where the extra reduction would cost more than the loop it shortens (measured on llvmpipe).
const GROUP_CHUNKS: u32 = 4u;
var<workgroup> positions: u32;

// Where the blocks' prefix sums start in `block_sums`: after a total for each block the pool can
// fill.
fn block_prefix_base() -> u32 {
    return (wave.pool + SCAN_WG - 1u) / SCAN_WG;
}

fn compact_blocks_main(lid: u32, wid: vec3<u32>, lanes: Lanes) {
    if lid == 0u {
        positions = atomicLoad(&counters[COUNTER_POSITIONS]);
    }
    let blocks = (workgroupUniformLoad(&positions) + SCAN_WG - 1u) / SCAN_WG;
    let first = wid.x * GROUP_CHUNKS * SCAN_WG;
    if first >= blocks {
        return;
    }
    let end = min(first + GROUP_CHUNKS * SCAN_WG, blocks);
    // The blocks before this group.
    var running = vec4<u32>(0u);
    if first > 0u {
        for (var i = lid; i < first; i += SCAN_WG) {
            running += block_sums[i];
        }
        scratch[lid] = running;
        scan_workgroup(lid, lanes);
        running = scratch[SCAN_WG - 1u];
        workgroupBarrier();
    }
    for (var base = first; base < end; base += SCAN_WG) {
        let i = base + lid;
        var v = vec4<u32>(0u);
        if i < end {
            v = block_sums[i];
        }
        scratch[lid] = v;
        scan_workgroup(lid, lanes);
        if i < end {
            block_sums[block_prefix_base() + i] = running + scratch[lid] - v;
        }
        running += scratch[SCAN_WG - 1u];
        // Every lane has read the total before the next chunk overwrites it.
        workgroupBarrier();
    }
    if lid == 0u && end == blocks {
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

fn compact_scatter_main(gid: vec3<u32>, wid: vec3<u32>) {
    let p = gid.x;
    if p >= atomicLoad(&counters[COUNTER_POSITIONS]) {
        return;
    }
    let q = next_queue[p];
    if q == DEAD {
        return;
    }
    let offset = block_sums[block_prefix_base() + wid.x];
    queues[q * wave.pool + offset[lane_of(q)] + scan_offset[p]] = scan_slot[p];
}
