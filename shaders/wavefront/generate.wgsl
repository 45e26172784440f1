// generate: camera paths. `generate` starts every path of a wave on the bounce-0 ray queue
// (--schedule waves); `regenerate_init` empties the pool at a share's start and `regenerate`
// starts the share's next samples in the slots whose paths ended (--schedule regenerate).
// Rust side: src/gpu/wavefront/generate.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/path_start.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn generate(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    let slot = gid.x;
    if slot == 0u {
        atomicStore(&counters[QUEUE_RAY_0], wave_paths());
        atomicStore(&counters[QUEUE_RAY_0 + 1u], 0u);
        // queue_setup_intersect advances this to 0 before the first bounce.
        atomicStore(&counters[COUNTER_BOUNCE], DEAD);
    }
    if slot >= wave_paths() {
        return;
    }
    instrument(PASS_GENERATE);
    start_path(slot, slot);
    // With camera rays made in place, intersect takes the wave's slots in order without a queue.
    if !CAMERA_IN_PLACE {
        queues[QUEUE_RAY_0 * wave.pool + slot] = slot;
    }
    if slot_order() {
        next_queue[slot] = DEAD; // intersect sets it: until then the slot goes nowhere
    }
}

// A share's start: every slot free, no queue holding anything, no sample started.
@compute @workgroup_size(WORKGROUP_SIZE)
fn regenerate_init(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    let slot = gid.x;
    if slot == 0u {
        for (var q = 0u; q < QUEUE_COUNT; q++) {
            atomicStore(&counters[q], 0u);
        }
        atomicStore(&counters[QUEUE_FREE], wave.pool);
        // queue_setup_intersect advances this to 0 before the first iteration.
        atomicStore(&counters[COUNTER_BOUNCE], DEAD);
        atomicStore(&counters[COUNTER_NEXT_SAMPLE], 0u);
        for (var c = 0u; c < wave.ring; c++) {
            atomicStore(&counters[COUNTER_RING_0 + c], 0u);
        }
    }
    if slot >= wave.pool {
        return;
    }
    queues[QUEUE_FREE * wave.pool + slot] = slot;
    path_dir[slot].w = bitcast<f32>(DEAD);
    if slot_order() {
        next_queue[slot] = DEAD; // no path: the scans skip it, and list it as free
    }
    if NEE && COMPACTION == COMPACTION_OFF {
        shadow_weight[slot] = vec4<f32>(0.0);
    }
}

// The refill: thread i starts sample (base + i) in the i-th free slot (in slot order, the i-th
// lowest, or the i-th of ascending runs, so consecutive samples land in neighbouring slots) and
// queues its camera ray for the coming iteration in the i-th ray-queue entry queue_setup_regenerate reserved (which
// also sized the pass and took the samples).
@compute @workgroup_size(WORKGROUP_SIZE)
fn regenerate(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    let base = atomicLoad(&counters[COUNTER_REGEN_BASE]);
    if gid.x >= atomicLoad(&counters[COUNTER_NEXT_SAMPLE]) - base {
        return;
    }
    instrument(PASS_GENERATE);
    let slot = queues[QUEUE_FREE * wave.pool + atomicLoad(&counters[COUNTER_FREE_BASE]) + gid.x];
    start_path(slot, base + gid.x);
    if COMPACTION != COMPACTION_OFF {
        let q = next_ray_queue();
        let mark = select(0u, CAMERA_RAY, CAMERA_IN_PLACE);
        queues[q * wave.pool + atomicLoad(&counters[COUNTER_REFILL_QUEUED]) + gid.x] = slot | mark;
    }
}
