// compact: builds dense queues by a stable prefix-sum scan (the `scan` compaction method) over
// the queue positions the previous pass processed (COUNTER_POSITIONS, dispatched indirectly), from
// the queue each position asked for in `next_queue`: cost follows the live paths, not the pool.
// Three passes: per-workgroup scan, scan of the workgroup totals (a workgroup per 1,024 of them),
// scatter. Lanes of a vec4 count up to four queues at once (the material queues after intersect;
// lane 0 = the next ray queue after shade).
// In slot order (`--queue-order slot`) `next_queue` is indexed by slot: the scan after intersect
// (scan method only) still covers the ray queue's positions (stable, so the material queues keep
// the ray queue's slot order), but the scan after shade (scan method, or the depth key with
// either method; plain slot order with atomic appends sweeps instead, slot_sweep.wgsl) covers
// every slot of the pool, so the next ray queue comes out in slot order, with the free list
// (lane 1) and the shadow queue (lane 2); keyed by depth (`slot-depth`), lane 3 lists the paths
// on their first bounce, placed after lane 0's in the same ray queue.
// The workgroup scan the first two passes run is a hook (wavefront/shared/scan.wgsl, without
// subgroups; the `--scan subgroup` variant swaps in scan_subgroup.wgsl): `scan_workgroup(at)`, an
// inclusive scan of `scratch`, where `at: ScanLane` holds the entry point's builtins it needs.
// Rust side: src/gpu/wavefront/compact.rs.

#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/scan.wgsl"

var<workgroup> scratch: array<vec4<u32>, SCAN_WG>;

// false: building the material queues (after intersect); true: the next ray queue (after shade).
override TARGET_RAYS: bool = false;

// After intersect a position's lanes are the material queues, one per kind: a vec4 holds four.
// A fifth kind needs wider flags (or a scan per four kinds); until then the build says so here.
const_assert MATERIAL_KIND_COUNT <= 4u;

fn one_hot(q: u32) -> vec4<u32> {
    if q == DEAD {
        return vec4<u32>(0u);
    }
    return vec4<u32>(vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(q - QUEUE_MATERIAL_0));
}

// The slot at scan position `p`: as the producing pass recorded it (arrival order); in slot
// order the intersected ray queue's p-th entry, without its camera-ray mark (after intersect),
// or p itself (after shade).
fn slot_at(p: u32) -> u32 {
    if !slot_order() {
        return scan_slot[p];
    }
    if TARGET_RAYS {
        return p;
    }
    return ray_queue_entry(p) & ~CAMERA_RAY;
}

// The queues position `p` goes to, one lane each: the material queues (after intersect); the
// next ray queue in lane 0 (after shade) and, in slot order, the free list (regenerate: every
// slot holding no path) in lane 1 and the shadow queue (a pending shadow ray) in lane 2. A slot
// can go to both the ray and the shadow queue.
fn scan_flags(p: u32) -> vec4<u32> {
    if !TARGET_RAYS {
        return one_hot(next_queue[select(p, slot_at(p), slot_order())]);
    }
    let q = next_queue[p];
    var f = vec4<u32>(u32(q != DEAD), 0u, 0u, 0u);
    if slot_order() {
        f.y = u32(REGENERATE && q == DEAD);
        f.z = u32(q != DEAD && (q & SHADOW_PENDING) != 0u);
    }
    if depth_key() && q != DEAD && (q & FIRST_BOUNCE) != 0u {
        f = vec4<u32>(0u, f.y, f.z, 1u);
    }
    return f;
}

// The queue lane `k` of the flags builds (DEAD: none). Keyed by depth, lanes 0 and 3 both build
// the next ray queue: lane 3's paths (first bounce) after lane 0's.
fn lane_queue(k: u32) -> u32 {
    if !TARGET_RAYS {
        return QUEUE_MATERIAL_0 + k;
    }
    switch k {
        case 0u: {
            return next_ray_queue();
        }
        case 1u: {
            return select(DEAD, QUEUE_FREE, REGENERATE && slot_order());
        }
        case 2u: {
            return select(DEAD, QUEUE_SHADOW, slot_order());
        }
        default: {
            return select(DEAD, next_ray_queue(), depth_key());
        }
    }
}

// Keyed by depth, where lane 3's run starts in the ray queue: after every lane-0 path (the last
// block's exclusive prefix plus its own total, both still in `block_sums` after the block pass).
fn lane_base() -> vec4<u32> {
    if !TARGET_RAYS || !depth_key() {
        return vec4<u32>(0u);
    }
    let blocks = (atomicLoad(&counters[COUNTER_POSITIONS]) + SCAN_WG - 1u) / SCAN_WG;
    let last = blocks - 1u;
    return vec4<u32>(0u, 0u, 0u, block_sums[block_prefix_base() + last].x + block_sums[last].x);
}

// Position `p`'s flags, none past the positions this scan covers.
fn flags_at(p: u32) -> vec4<u32> {
    if p < atomicLoad(&counters[COUNTER_POSITIONS]) {
        return scan_flags(p);
    }
    return vec4<u32>(0u);
}

@compute @workgroup_size(SCAN_WG)
fn compact_scan(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
                at: ScanLane) {
    let lid = at.lid;
    let p = gid.x;
    let v = flags_at(p);
    scratch[lid] = v;
    scan_workgroup(at);
    // Each lane's offset within the workgroup, below SCAN_WG = 256: a byte each.
    if any(v != vec4<u32>(0u)) {
        let offset = scratch[lid] - v;
        scan_offset[p] = offset.x | (offset.y << 8u) | (offset.z << 16u) | (offset.w << 24u);
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

@compute @workgroup_size(SCAN_WG)
fn compact_blocks(@builtin(workgroup_id) wid: vec3<u32>, at: ScanLane) {
    let lid = at.lid;
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
        scan_workgroup(at);
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
        scan_workgroup(at);
        if i < end {
            block_sums[block_prefix_base() + i] = running + scratch[lid] - v;
        }
        running += scratch[SCAN_WG - 1u];
        // Every lane has read the total before the next chunk overwrites it.
        workgroupBarrier();
    }
    if lid == 0u && end == blocks {
        // Keyed by depth, the ray queue holds lanes 0 and 3.
        var count = running;
        if TARGET_RAYS && depth_key() {
            count.x += count.w;
            count.w = count.x;
        }
        for (var k = 0u; k < 4u; k++) {
            let q = lane_queue(k);
            if q != DEAD {
                atomicStore(&counters[q], count[k]);
            }
        }
    }
}

@compute @workgroup_size(SCAN_WG)
fn compact_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let p = gid.x;
    let v = flags_at(p);
    if all(v == vec4<u32>(0u)) {
        return;
    }
    var slot = slot_at(p);
    // (--refill in-place, slot order) A slot just refilled goes on the ray queue marked: its
    // camera ray is made in intersect. (DEAD, every bit set, is a free slot; a refilled one has
    // no shadow ray, so no other lane.)
    if REFILL_IN_PLACE && TARGET_RAYS && slot_order() {
        let mark = next_queue[p];
        if mark != DEAD && (mark & NEW_CAMERA) != 0u {
            slot |= CAMERA_RAY;
        }
    }
    let packed = scan_offset[p];
    let offset = lane_base() + block_sums[block_prefix_base() + wid.x]
        + (vec4<u32>(packed) >> vec4<u32>(0u, 8u, 16u, 24u)) % 256u;
    for (var k = 0u; k < 4u; k++) {
        if v[k] != 0u {
            queues[lane_queue(k) * wave.pool + offset[k]] = slot;
        }
    }
}
