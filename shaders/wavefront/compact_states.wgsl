// compact_states (--compact-states on, regenerating): before a refill, move the live paths that
// sit above the live count into the free slots below it, as Cycles' compact_states does, so that
// every live path is in slots [0, live) and the refill's consecutive samples take the contiguous
// slots from `live` on, in sample order (one run of neighbouring pixels, as in a wave) instead
// of wherever paths happened to end. Moves are disjoint (from slots >= live into free slots
// < live, equal in number), so one pass does them all; each moved path's ray-queue entry is
// rewritten in place, so the queue keeps its order and length.
// Rust side: src/gpu/wavefront/compact_states.rs.
//
//   queue_setup_regenerate   sizes the refill; when it refills, the find pass too
//   compact_states_find      lists the holes (free slots < live) and the movers' queue positions
//   queue_setup_compact      sizes the move pass
//   compact_states_move      moves the states; rewrites the free list as slots [live, pool)
//   regenerate               the refill takes free-list entries from COUNTER_FREE_BASE on

// The scene's includes for its pipeline constants (NEE); the no-op instrument hook that
// traversal code names. No instrumented variant is used: nothing here is counted.
#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

// Scratch lists in queue regions no pass reads between a refill and the next intersect (which
// empties the material queues): the holes, and the ray-queue positions of the paths to move.
const HOLES: u32 = QUEUE_MATERIAL_0;
const MOVERS: u32 = QUEUE_MATERIAL_0 + 1u;

// Live paths at the refill: every slot not on the free list (those on the ray queue, tail-finished
// ones included until the next intersect frees them).
fn live_paths() -> u32 {
    return wave.pool - atomicLoad(&counters[COUNTER_COMPACT_FREE]);
}

// Thread i looks at ray-queue position i (a path in a slot >= live must move down) and at
// free-list entry i (a free slot < live is a hole to fill).
@compute @workgroup_size(WORKGROUP_SIZE)
fn compact_states_find(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    let live = live_paths();
    if i < atomicLoad(&counters[COUNTER_REFILL_QUEUED]) {
        if queues[next_ray_queue() * wave.pool + i] >= live {
            queues[MOVERS * wave.pool + atomicAdd(&counters[MOVERS], 1u)] = i;
        }
    }
    if i < atomicLoad(&counters[COUNTER_COMPACT_FREE]) {
        let slot = queues[QUEUE_FREE * wave.pool + i];
        if slot < live {
            queues[HOLES * wave.pool + atomicAdd(&counters[HOLES], 1u)] = slot;
        }
    }
}

// Thread i moves the i-th mover into the i-th hole, and writes free-list entry i: the free
// slots are now exactly [live, pool), laid out so that the refill's thread t (entry
// COUNTER_FREE_BASE + t) takes slot live + t, whether the refill reads a stack's top (arrival
// order) or the list's start (slot order, base 0).
@compute @workgroup_size(WORKGROUP_SIZE)
fn compact_states_move(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    let live = live_paths();
    let movers = atomicLoad(&counters[MOVERS]);
    // Equal unless the free list and the ray queue disagree (a bug): then nothing moves and the
    // free list stays as it was, so no path is lost; the host refuses the render.
    if movers != atomicLoad(&counters[HOLES]) {
        if i == 0u {
            atomicAdd(&counters[COUNTER_COMPACT_MISMATCH], 1u);
        }
        return;
    }
    if i < movers {
        let position = next_ray_queue() * wave.pool + queues[MOVERS * wave.pool + i];
        let from_slot = queues[position];
        let to_slot = queues[HOLES * wave.pool + i];
        path_origin[to_slot] = path_origin[from_slot];
        path_dir[to_slot] = path_dir[from_slot];
        path_throughput[to_slot] = path_throughput[from_slot];
        radiance[to_slot] = radiance[from_slot];
        path_sample[to_slot] = path_sample[from_slot];
        if NEE {
            shadow_weight[to_slot] = shadow_weight[from_slot];
            shadow_weight[from_slot] = vec4<f32>(0.0);
        }
        if slot_order() {
            next_queue[to_slot] = next_queue[from_slot];
            next_queue[from_slot] = DEAD;
        }
        path_dir[from_slot].w = bitcast<f32>(DEAD);
        queues[position] = to_slot;
    }
    let free = atomicLoad(&counters[COUNTER_COMPACT_FREE]);
    if i < free {
        let base = atomicLoad(&counters[COUNTER_FREE_BASE]);
        let taken = atomicLoad(&counters[COUNTER_NEXT_SAMPLE]) - atomicLoad(&counters[COUNTER_REGEN_BASE]);
        queues[QUEUE_FREE * wave.pool + i] = live + select(taken + i, i - base, i >= base);
    }
    if i == 0u {
        atomicAdd(&counters[COUNTER_STATES_MOVED], movers);
        atomicAdd(&counters[COUNTER_COMPACTIONS], 1u);
    }
}
