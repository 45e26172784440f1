// shadow (--nee on): the shadow rays the shade passes queued, an any-hit query each; an unblocked
// one adds its light to the path's radiance. Its own queue and pass, as in pbrt-v4 and Cycles, so
// the cheap any-hit traversal runs converged instead of inside the shade passes.
// Rust side: src/gpu/wavefront/shadow.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn shadow(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    bvh_stack_lane(gid.x);
    // (No launched_past_done here: queue_setup_shadow_decide may set DONE just before this pass,
    // whose shadow rays are the share's own; past the end, shade queues none.)
    let slot = queued_slot(QUEUE_SHADOW, gid.x);
    if slot == DEAD {
        return;
    }
    let w = shadow_weight[slot];
    // w holds the bits of the light's slot + 1 (compared as bits: as a float it is subnormal).
    let light = bitcast<u32>(w.w);
    if light == 0u {
        return; // only without compaction: no shadow ray pending at this slot
    }
    instrument(PASS_SHADOW);
    let r = shadow_ray[slot];
    var add = vec4<f32>(0.0, 0.0, 0.0, 1.0); // one more ray traced
    let ray = Ray(path_origin[slot].xyz, r.xyz);
    instrument_traversal(PASS_SHADOW_TRAVERSE);
    // path_dir.w: the primitive the shadow ray left (shade wrote it with the next ray).
    if shadow_unblocked(ray, r.w, light - 1u, bitcast<u32>(path_dir[slot].w)) {
        add += vec4<f32>(w.xyz, 0.0);
    }
    radiance[slot] += add;
    if COMPACTION == COMPACTION_OFF {
        shadow_weight[slot].w = 0.0; // without queues the pending mark is all that says it ran
    }
}
