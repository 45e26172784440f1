// slot_sweep: in slot order with the atomic compaction method (`--queue-order slot`), builds the
// next ray queue, the free list (regenerate) and the shadow queue in one pass over the pool's
// slots, from the queue each slot asked for in `next_queue`, with appends. With appends
// aggregated per subgroup (`--append`, wavefront/shared/append_subgroup.wgsl) each subgroup writes its
// slots as one run in ascending order, so a queue is a sequence of runs of neighbouring slots
// (the runs' order is the atomics'): a later pass's subgroup reads as few lines of path state as
// in the scan's exact slot order (the coherence counters), though the runs no longer form one
// ascending stream, at one pass without barriers instead of the scan's three (on llvmpipe about
// a third of the scan's time: commit 5f22f9a). The scan method, and the depth key (which places
// a run after all others, so needs their total), keep the stable scan (wavefront/compact.wgsl).
// Rust side: src/gpu/wavefront/slot_sweep.rs.

#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/append.wgsl"

// Dispatched with the scan's indirect arguments (queue_setup_shade's set_compact_args): SCAN_WG
// threads a workgroup over COUNTER_POSITIONS = every slot of the pool.

@compute @workgroup_size(SCAN_WG)
fn slot_sweep(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.x;
    if slot >= atomicLoad(&counters[COUNTER_POSITIONS]) {
        return;
    }
    let q = next_queue[slot];
    if q == DEAD {
        if REGENERATE {
            append(QUEUE_FREE, slot);
        }
        return;
    }
    // (--refill in-place) A slot just refilled: its camera ray is made in intersect.
    append(next_ray_queue(), slot | select(0u, CAMERA_RAY, REFILL_IN_PLACE && (q & NEW_CAMERA) != 0u));
    if (q & SHADOW_PENDING) != 0u {
        append(QUEUE_SHADOW, slot);
    }
}
