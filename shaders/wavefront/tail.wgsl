// tail (--tail megakernel): when few paths are left in a regenerating chunk, one pass finishes
// each of them megakernel-style, every remaining bounce in one thread (Cycles X ends a frame
// this way), instead of a near-empty round of passes per bounce. Takes the ray queue the last
// shade pass filled; the path loop is the megakernel's (shared/integrator.wgsl), so a sample
// comes out as it would from the passes. Rust side: src/gpu/wavefront/tail.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/path_state.wgsl"
#include "shared/instrument.wgsl"
#include "shared/integrator.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn tail(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = queued_slot(QUEUE_RAY_0 + (current_bounce() + 1u) % 2u, gid.x);
    if slot == DEAD {
        return;
    }
    let d = path_dir[slot];
    if bitcast<u32>(d.w) == DEAD {
        return; // only without compaction: an ended path in the pool
    }
    let o = path_origin[slot];
    let t = path_throughput[slot];
    let r = radiance[slot];
    var path = TracedPath(Ray(o.xyz, d.xyz), t.xyz, r.xyz, u32(r.w), t.w, bitcast<u32>(d.w));
    continue_path(&path, slot_pixel(slot), slot_sample(slot), path_bounce(slot));
    radiance[slot] = vec4<f32>(path.radiance, f32(path.rays));
    path_dir[slot].w = bitcast<f32>(DEAD);
    finish_path(slot);
}
