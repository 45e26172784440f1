// Where a path starts and ends in a slot: generate's and the refill pass's camera paths, the
// end of a path in intersect or shade, and (--refill in-place) the next sample started in the
// slot of a path that just ended. Included by generate, intersect and shade.

#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/path_camera.wgsl"

// The path in `slot` has ended at `bounce` with `value` (rgb: its radiance; w: the shadow rays it
// traced): final once its rays are counted (w + the bounce + 1 rays it traced, added here so that
// intersect need not touch `radiance` on a hit). Computed by the caller in registers and written
// once: regenerating, straight into the sample ring (and the slot to the free queue, for the next
// iteration's refill); in waves into `radiance`, which the accumulate pass reads.
// `refilled`: the counter of slots refilled in place by the calling pass.
fn finish_path(slot: u32, bounce: u32, value: vec4<f32>, refilled: u32) {
    let done = value + vec4<f32>(0.0, 0.0, 0.0, f32(bounce + 1u));
    if REGENERATE {
        store_sample(slot, done);
        if !refill_in_place(slot, refilled) {
            free_slot(slot);
        }
    } else {
        radiance[slot] = done;
    }
}

// (regenerate, --refill in-place) The slot of a path that just ended starts the share's next
// sample, if the sample ring has room for it (its fill limit), as the refill pass would start it
// in a free slot, and queues the camera ray for the next iteration (in slot order: marks the slot
// for the pass after shade, which queues it); counted in `refilled`. The
// sample is claimed by a ticket (one atomic add, no compare-and-swap loop): ticket k is the
// sample k past the share's next, which no pass moves until `settle_claims`, so claims past
// the limit simply fail and the slot goes to the free list.
fn refill_in_place(slot: u32, refilled: u32) -> bool {
    if !REFILL_IN_PLACE {
        return false;
    }
    let l = atomicLoad(&counters[COUNTER_NEXT_SAMPLE]) + take_ticket(COUNTER_CLAIMS);
    let limit = min(atomicLoad(&counters[COUNTER_FILL_LIMIT]), wave_paths());
    if l >= limit {
        return false;
    }
    start_path(slot, l);
    let camera = CAMERA_IN_PLACE;
    if slot_order() {
        // The pass after shade lists the slot on the ray queue (overwriting retire's DEAD).
        next_queue[slot] = next_ray_queue() | select(0u, NEW_CAMERA, camera);
    } else {
        append(next_ray_queue(), slot | select(0u, CAMERA_RAY, camera));
    }
    count_one(refilled);
    return true;
}

// Slot `slot` starts tracing sample `l` of the share: its camera ray, at bounce 0 (generate,
// the refill pass, and a refill in place).
fn start_path(slot: u32, l: u32) {
    if REGENERATE {
        path_sample[slot] = vec2<u32>(l, 0u);
    }
    if !CAMERA_IN_PLACE {
        let ray = sample_camera_ray(l);
        path_origin[slot] = vec4<f32>(ray.origin, 0.0);
        // w: the primitive the ray leaves, none (intersect counts self-hits against it).
        path_dir[slot] = vec4<f32>(ray.dir, bitcast<f32>(NO_ORIGIN));
    }
    // No throughput or radiance: a camera ray's are known (path_throughput_at, path_radiance).
    // Without queues the shadow pass visits every slot and skips those with no shadow ray
    // pending; with them only queued shadow rays are visited, and their weight is written first.
    if NEE && COMPACTION == COMPACTION_OFF {
        shadow_weight[slot] = vec4<f32>(0.0);
    }
}
