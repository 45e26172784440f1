// generate: a camera ray for every path of the wave, all on the bounce-0 ray queue.
// Rust side: src/gpu/wavefront/generate.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/path_state.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn generate(@builtin(global_invocation_id) gid: vec3<u32>) {
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
    let pixel = slot_pixel(slot);
    let x = pixel % frame.width;
    let y = pixel / frame.width;
    let ray = camera_ray(x, y, uniform4(pixel, slot_sample(slot), 0u, PURPOSE_CAMERA, frame.seed));
    path_origin[slot] = vec4<f32>(ray.origin, 0.0);
    path_dir[slot] = vec4<f32>(ray.dir, 0.0);
    path_throughput[slot] = vec4<f32>(1.0, 1.0, 1.0, 0.0);
    radiance[slot] = vec4<f32>(0.0);
    if NEE {
        shadow_weight[slot] = vec4<f32>(0.0);
    }
    queues[QUEUE_RAY_0 * wave.pool + slot] = slot;
}
