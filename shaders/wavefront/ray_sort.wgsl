// ray_sort (--ray-sort octant|octant-cell): orders the ray queue by a key before intersect, so
// that a subgroup's lanes trace rays that leave in the same direction octant (and, with
// octant-cell, from the same cell of a 4x4x4 grid over the scene's bounds, in Morton order):
// Garanzha & Loop's ray sort, as a counting sort of three passes.
// Rust side: src/gpu/wavefront/ray_sort.rs.
//
//   queue_setup_intersect  sizes intersect (and these passes) from the ray queue's count
//   ray_sort_count        copies the queue and each entry's key aside; counts entries per key
//   ray_sort_scan         one workgroup: each key's first position; clears the counts
//   ray_sort_scatter      writes the queue back, key by key
//
// Each workgroup counts its keys in workgroup memory and makes one global atomic per key it
// holds, so the passes cost a few operations per ray even when most rays share a key. Within a
// key the order is the order of the workgroups' reservations and their lanes' atomics: not
// stable. The film does not depend on the queue's order (each sample's random numbers and its
// place in the film are its own), so it stays bit-identical.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;
// Bits per axis of the origin cell: 0 (octant alone) or 2 (octant-cell: 4x4x4 cells).
override CELL_BITS: u32 = 0u;

// Keys: octant (3 bits) above the cell's Morton code (3 x CELL_BITS bits); at most 2^9.
const KEYS: u32 = 512u;
// Largest workgroup (the scan's is exactly this: two keys a thread).
const MAX_WG: u32 = 256u;
// Scratch copies in queue regions that no pass reads between queue_setup_intersect (which
// empties the material queues) and intersect (which fills them): the queue's slots and keys.
const SLOTS: u32 = QUEUE_MATERIAL_0;
const KEYS_ASIDE: u32 = QUEUE_MATERIAL_0 + 1u;

// [0, KEYS): entries per key (count pass); [KEYS, 2 KEYS): each key's next position (scatter).
@group(2) @binding(0) var<storage, read_write> buckets: array<atomic<u32>>;

// Keys in use: octant (8) x cells (8^CELL_BITS).
fn keys_used() -> u32 {
    return 8u << (3u * CELL_BITS);
}

var<workgroup> wg_count: array<atomic<u32>, KEYS>;
var<workgroup> wg_base: array<u32, KEYS>;
var<workgroup> scan: array<u32, MAX_WG>;

// The intersect queue of this iteration (queue_setup_intersect has advanced the bounce).
fn ray_queue() -> u32 {
    return QUEUE_RAY_0 + current_bounce() % 2u;
}

// Spreads the low CELL_BITS bits of `v` three apart (Morton interleave).
fn spread_bits(v: u32) -> u32 {
    var out = 0u;
    for (var b = 0u; b < CELL_BITS; b++) {
        out |= ((v >> b) & 1u) << (3u * b);
    }
    return out;
}

fn ray_key(slot: u32) -> u32 {
    let d = path_dir[slot].xyz;
    let octant = select(0u, 1u, d.x < 0.0) | select(0u, 2u, d.y < 0.0) | select(0u, 4u, d.z < 0.0);
    if CELL_BITS == 0u {
        return octant;
    }
    // The root node's box bounds every primitive (one node without a BVH too).
    let lo = bvh_root_min();
    let extent = max(bvh_root_max() - lo, vec3<f32>(1e-30));
    let cells = f32(1u << CELL_BITS);
    let c = vec3<u32>(clamp((path_origin[slot].xyz - lo) / extent * cells, vec3<f32>(0.0), vec3<f32>(cells - 1.0)));
    let morton = spread_bits(c.x) | spread_bits(c.y) << 1u | spread_bits(c.z) << 2u;
    return octant << (3u * CELL_BITS) | morton;
}

fn clear_workgroup_counts(lane: u32) {
    for (var k = lane; k < keys_used(); k += WORKGROUP_SIZE) {
        atomicStore(&wg_count[k], 0u);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn ray_sort_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    clear_workgroup_counts(lane);
    workgroupBarrier();
    let i = gid.x;
    let q = ray_queue();
    if i < atomicLoad(&counters[q]) {
        let slot = queues[q * wave.pool + i];
        let key = ray_key(slot);
        queues[SLOTS * wave.pool + i] = slot;
        queues[KEYS_ASIDE * wave.pool + i] = key;
        atomicAdd(&wg_count[key], 1u);
    }
    workgroupBarrier();
    for (var k = lane; k < keys_used(); k += WORKGROUP_SIZE) {
        let n = atomicLoad(&wg_count[k]);
        if n > 0u {
            atomicAdd(&buckets[k], n);
        }
    }
}

// One workgroup of MAX_WG threads, two keys each: exclusive prefix sums of the counts (each
// key's first position), and the counts cleared for the next iteration's sort.
@compute @workgroup_size(MAX_WG)
fn ray_sort_scan(@builtin(local_invocation_index) t: u32) {
    let a = atomicLoad(&buckets[2u * t]);
    let b = atomicLoad(&buckets[2u * t + 1u]);
    scan[t] = a + b;
    workgroupBarrier();
    // Hillis-Steele inclusive scan over the pair sums.
    for (var step = 1u; step < MAX_WG; step *= 2u) {
        var add = 0u;
        if t >= step {
            add = scan[t - step];
        }
        workgroupBarrier();
        scan[t] += add;
        workgroupBarrier();
    }
    let start = scan[t] - a - b;
    atomicStore(&buckets[KEYS + 2u * t], start);
    atomicStore(&buckets[KEYS + 2u * t + 1u], start + a);
    atomicStore(&buckets[2u * t], 0u);
    atomicStore(&buckets[2u * t + 1u], 0u);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn ray_sort_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    clear_workgroup_counts(lane);
    workgroupBarrier();
    let i = gid.x;
    let q = ray_queue();
    let queued = i < atomicLoad(&counters[q]);
    var key = 0u;
    var rank = 0u;
    if queued {
        key = queues[KEYS_ASIDE * wave.pool + i];
        rank = atomicAdd(&wg_count[key], 1u);
    }
    workgroupBarrier();
    // One reservation per key the workgroup holds.
    for (var k = lane; k < keys_used(); k += WORKGROUP_SIZE) {
        let n = atomicLoad(&wg_count[k]);
        if n > 0u {
            wg_base[k] = atomicAdd(&buckets[KEYS + k], n);
        }
    }
    workgroupBarrier();
    if queued {
        queues[q * wave.pool + wg_base[key] + rank] = queues[SLOTS * wave.pool + i];
    }
}
