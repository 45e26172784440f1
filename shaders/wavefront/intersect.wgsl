// intersect: the closest hit of every queued ray (the megakernel's BVH traversal). Escaped rays
// add the background and end; hits go to their material's queue. Rust: src/gpu/wavefront/intersect.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/path_start.wgsl"
#include "shared/instrument.wgsl"
#include "wavefront/shared/coherence.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn intersect(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    bvh_stack_lane(gid.x);
    let entry = ray_queue_entry(gid.x);
    if entry == DEAD || launched_past_done() {
        return;
    }
    let slot = entry & ~CAMERA_RAY;
    // A camera ray made here (CAMERA_IN_PLACE): regenerating, the refill marked its entry; in
    // waves every path is at the iteration's bounce.
    var camera = false;
    if CAMERA_IN_PLACE {
        if REGENERATE {
            camera = (entry & CAMERA_RAY) != 0u;
        } else {
            camera = current_bounce() == 0u;
        }
    }
    var ray: Ray;
    // The primitive the ray left (set by shade, NO_ORIGIN for a camera ray).
    var left = NO_ORIGIN;
    if camera {
        ray = sample_camera_ray(slot_index(slot));
    } else {
        let dir = path_dir[slot];
        if bitcast<u32>(dir.w) == DEAD {
            return; // only without compaction: an ended path in the pool
        }
        if REGENERATE && bitcast<u32>(dir.w) == FLUSHED {
            // The tail finished this path after it was queued: off the queue now, so free.
            path_dir[slot].w = bitcast<f32>(DEAD);
            free_slot(slot);
            retire(slot, gid.x);
            if COMPACTION != COMPACTION_OFF {
                atomicSub(&counters[COUNTER_INTERSECTED], 1u); // queued, but no ray traced
            }
            return;
        }
        ray = Ray(path_origin[slot].xyz, dir.xyz);
        left = bitcast<u32>(dir.w);
    }
    instrument(PASS_INTERSECT);
    instrument_coherence(slot, ray.dir);
    instrument_traversal(PASS_INTERSECT_TRAVERSE);
    let hit = closest_hit(ray, frame.t_min);
    if hit.prim == NO_HIT {
        let bounce = select(path_bounce(slot), 0u, camera);
        let sky = path_throughput_at(slot, bounce).xyz * background(ray.dir);
        path_dir[slot].w = bitcast<f32>(DEAD);
        retire(slot, gid.x);
        finish_path(slot, bounce, path_radiance(slot, bounce) + vec4<f32>(sky, 0.0), COUNTER_REFILLED_INTERSECT);
        return;
    }
    if is_self_hit(left, hit.prim, ray, hit.t) {
        count_failure(FAILURE_SELF_HIT);
    }
    path_origin[slot].w = hit.t;
    path_dir[slot].w = bitcast<f32>(hit.prim);
    if REGENERATE && camera {
        count_one(COUNTER_CAMERA_HITS);
    }
    var q = QUEUE_MATERIAL_0;
    if SHADE_PASSES != SHADE_SINGLE {
        let m = materials[primitive(hit.prim).material];
        q += m.kind;
        // --shade per-texture: a costly pattern's hits go to that pattern's queue (only lambertian
        // and metal records carry one).
        if SHADE_PASSES == SHADE_PER_TEXTURE && m.texture >= TEXTURE_NOISE {
            q = QUEUE_PATTERN_0 + m.texture - TEXTURE_NOISE;
        }
    }
    enqueue(q, slot, gid.x);
}
