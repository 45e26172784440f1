// tail (--tail megakernel): one pass finishes paths megakernel-style, every remaining bounce in
// one thread (as early Cycles X did on the GPU below 2% of its path states), instead of a
// near-empty round of passes per bounce: the last paths of a share, and the few left of the
// oldest chunks when the sample ring needs them back. Takes the ray queue the last shade pass
// filled and finishes the paths of samples below COUNTER_TAIL_BOUND; the path loop is the
// megakernel's (shared/integrator.wgsl), so a sample comes out as it would from the passes.
// Rust side: src/gpu/wavefront/tail.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/path_camera.wgsl"
#include "shared/instrument.wgsl"
#include "shared/integrator.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn tail(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    bvh_stack_lane(gid.x);
    let q = next_ray_queue();
    let entry = queued_entry(q, gid.x);
    if entry == DEAD {
        return;
    }
    let slot = entry & ~CAMERA_RAY;
    // (--refill in-place) A camera ray queued where its slot was refilled: nothing stored but
    // the sample.
    let camera = REFILL_IN_PLACE && (entry & CAMERA_RAY) != 0u;
    var d = vec4<f32>(0.0, 0.0, 0.0, bitcast<f32>(NO_ORIGIN));
    if !camera {
        d = path_dir[slot];
        if bitcast<u32>(d.w) == DEAD || bitcast<u32>(d.w) == FLUSHED {
            return; // only without compaction: an ended path in the pool
        }
    }
    if slot_index(slot) >= atomicLoad(&counters[COUNTER_TAIL_BOUND]) {
        return; // a younger chunk's path: the passes go on with it
    }
    var bounce = 0u;
    var path = TracedPath(Ray(vec3<f32>(0.0), d.xyz), vec3<f32>(1.0), vec3<f32>(0.0), 0u, 0.0, NO_ORIGIN);
    if camera {
        path.ray = sample_camera_ray(slot_index(slot));
        // The entry unmarked, so the next intersect reads the FLUSHED mark and frees the slot.
        queues[q * wave.pool + gid.x] = slot;
    } else {
        bounce = path_bounce(slot);
        let t = path_throughput_at(slot, bounce);
        let r = path_radiance(slot, bounce);
        // r.w: the shadow rays traced so far; the path traced `bounce` rays before this one.
        path = TracedPath(Ray(path_origin[slot].xyz, d.xyz), t.xyz, r.xyz, u32(r.w) + bounce, t.w, bitcast<u32>(d.w));
    }
    // One call of the megakernel's loop (inlined once): the tail's code stays its size.
    continue_path(&path, slot_pixel(slot), slot_sample(slot), bounce);
    // Still on the ray queue: the next intersect frees the slot.
    path_dir[slot].w = bitcast<f32>(FLUSHED);
    store_sample(slot, vec4<f32>(path.radiance, f32(path.rays)));
}
