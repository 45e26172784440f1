// The megakernel: one thread traces one whole path, every bounce and every material in one
// loop, as the seeds' CUDA and OpenGL ports did. Rust side: src/gpu/megakernel.rs.
//
// A dispatch covers pixel_count pixels × sample_count samples, one thread each; radiance goes to
// `samples` and the accumulate pass adds it to the film in sample order. One path per thread
// keeps every loop short: llvmpipe ends any shader's loops after 65535 iterations in total.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/dispatch.wgsl"
#include "shared/instrument.wgsl"
#include "shared/integrator.wgsl"

@group(1) @binding(0) var<storage, read_write> samples: array<vec4<f32>>;
@group(1) @binding(1) var<uniform> dispatch: Dispatch;

override WORKGROUP_SIZE: u32 = 64u;

// Twin of src/cpu/integrator.rs::trace_path: rgb radiance, w rays traced.
fn trace_path(x: u32, y: u32, sample: u32) -> vec4<f32> {
    let pixel = y * frame.width + x;
    let ray = camera_ray(x, y, uniform4(pixel, sample, 0u, PURPOSE_CAMERA, frame.seed));
    var path = TracedPath(ray, vec3<f32>(1.0), vec3<f32>(0.0), 0u, 0.0, NO_ORIGIN);
    continue_path(&path, pixel, sample, 0u);
    return vec4<f32>(path.radiance, f32(path.rays));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn megakernel(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    bvh_stack_lane(gid.x);
    let i = gid.x;
    if i >= dispatch.pixel_count * dispatch.sample_count {
        return;
    }
    // Neighbouring threads take neighbouring pixels of the same sample: coherent camera rays.
    let pixel = dispatch.pixel_offset + i % dispatch.pixel_count;
    let sample = dispatch.sample_start + i / dispatch.pixel_count;
    samples[i] = trace_path(pixel % frame.width, pixel / frame.width, sample);
}
