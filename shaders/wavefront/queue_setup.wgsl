// queue_setup: turns queue counters into indirect-dispatch arguments on the GPU, so the host
// never reads a counter back inside the bounce loop (vello's *_setup passes); also resets the
// queues about to be filled and adds queue sizes to the bounce histogram.
// Rust side: src/gpu/wavefront/queue_setup.rs.

#include "shared/path_state.wgsl"

// Its own group: a buffer bound as storage cannot also feed an indirect dispatch in the same
// pass, so only this pass binds it.
@group(2) @binding(0) var<storage, read_write> indirect: array<u32>;

// Bounces past the last histogram row are added to it (at most 64: COUNTER_SHADE_BASE follows).
override STATS_BOUNCES: u32 = 64u;
// Workgroup size of the compact passes (compact.wgsl).
const SCAN_WG: u32 = 256u;
override WORKGROUP_SIZE: u32 = 64u;

fn set_args(slot: u32, threads: u32) {
    indirect[3u * slot] = (threads + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    indirect[3u * slot + 1u] = 1u;
    indirect[3u * slot + 2u] = 1u;
}

fn record(bounce: u32, q: u32, n: u32) {
    if wave.compaction != 0u {
        let row = min(bounce, STATS_BOUNCES - 1u);
        atomicAdd(&counters[COUNTER_STATS + row * QUEUE_COUNT + q], n);
    }
}

// Before intersect: advance the bounce, size the intersect pass, empty the material queues.
@compute @workgroup_size(1)
fn queue_setup_intersect() {
    let bounce = atomicAdd(&counters[COUNTER_BOUNCE], 1u) + 1u;
    let q = QUEUE_RAY_0 + bounce % 2u;
    var n = wave_paths();
    if wave.compaction != 0u {
        n = atomicLoad(&counters[q]);
    }
    set_args(ARGS_INTERSECT, n);
    record(bounce, QUEUE_RAY_0, n);
    // A scan after intersect covers the ray queue's positions.
    atomicStore(&counters[COUNTER_POSITIONS], n);
    indirect[3u * ARGS_COMPACT] = (n + SCAN_WG - 1u) / SCAN_WG;
    indirect[3u * ARGS_COMPACT + 1u] = 1u;
    indirect[3u * ARGS_COMPACT + 2u] = 1u;
    for (var k = 0u; k < 4u; k++) {
        atomicStore(&counters[QUEUE_MATERIAL_0 + k], 0u);
    }
}

// Before shade: size each shade pass, empty the next bounce's ray queue.
@compute @workgroup_size(1)
fn queue_setup_shade() {
    let bounce = current_bounce();
    var positions = 0u;
    for (var k = 0u; k < 4u; k++) {
        var n = wave_paths();
        if wave.compaction != 0u {
            n = atomicLoad(&counters[QUEUE_MATERIAL_0 + k]);
        }
        set_args(ARGS_SHADE_0 + k, n);
        record(bounce, QUEUE_MATERIAL_0 + k, n);
        atomicStore(&counters[COUNTER_SHADE_BASE + k], positions);
        positions += n;
    }
    // A scan after shade covers the material queues laid end to end.
    atomicStore(&counters[COUNTER_POSITIONS], positions);
    indirect[3u * ARGS_COMPACT] = (positions + SCAN_WG - 1u) / SCAN_WG;
    indirect[3u * ARGS_COMPACT + 1u] = 1u;
    indirect[3u * ARGS_COMPACT + 2u] = 1u;
    atomicStore(&counters[QUEUE_RAY_0 + (bounce + 1u) % 2u], 0u);
    atomicStore(&counters[QUEUE_SHADOW], 0u);
}

// Before the shadow pass (--nee on): size it from the shadow rays the shade passes queued.
@compute @workgroup_size(1)
fn queue_setup_shadow() {
    var n = wave_paths();
    if wave.compaction != 0u {
        n = atomicLoad(&counters[QUEUE_SHADOW]);
    }
    set_args(ARGS_SHADOW, n);
    record(current_bounce(), QUEUE_SHADOW, n);
}
