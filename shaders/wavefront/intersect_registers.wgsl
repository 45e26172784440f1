// intersect_registers: a diagnostic twin of intersect (issue 44, item 1b; `wavetrace
// intersect-cost`). Each thread makes its camera ray in place, exactly as generate makes it for
// path sample i of a one-share wave, traces it with the same closest_hit as intersect, and keeps
// only a tally: no path state is read or written. Its time against intersect's for the same
// camera rays splits traversal from the state traffic around it. Rust:
// src/gpu/wavefront/intersect_registers.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
// The no-op hook the traversal calls (build.rs also writes an instrumented variant; none runs it).
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;

struct CameraRays {
    // Rays to trace: path samples 0..count, sample i at pixel i % pixel_count.
    count: u32,
    pixel_count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(1) @binding(0) var<uniform> camera_rays: CameraRays;
// Hits, and the wrapping sum of (hit primitive + 1) over them: the hits can be checked against
// intersect's, and the traversal cannot be compiled away.
@group(1) @binding(1) var<storage, read_write> tally: array<atomic<u32>, 2>;

// The workgroup's tally, added to `tally` once per workgroup so that the atomics cost nothing
// beside the traversal.
var<workgroup> group_hits: atomic<u32>;
var<workgroup> group_sum: atomic<u32>;

// A 2D grid of workgroups (x at most the device's limit), so one dispatch covers a 1080p frame's
// 64 samples a pixel.
@compute @workgroup_size(WORKGROUP_SIZE)
fn intersect_registers(
    @builtin(local_invocation_index) lane: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = (wid.y * groups.x + wid.x) * WORKGROUP_SIZE + lane;
    bvh_stack_lane(lane);
    if i < camera_rays.count {
        // generate's start_path for sample i of a share of every pixel from sample 0.
        let pixel = i % camera_rays.pixel_count;
        let sample = i / camera_rays.pixel_count;
        let u = uniform4(pixel, sample, 0u, PURPOSE_CAMERA, frame.seed);
        let ray = camera_ray(pixel % frame.width, pixel / frame.width, u);
        let hit = closest_hit(ray, frame.t_min);
        if hit.prim != NO_HIT {
            atomicAdd(&group_hits, 1u);
            atomicAdd(&group_sum, hit.prim + 1u);
        }
    }
    workgroupBarrier();
    if lane == 0u {
        atomicAdd(&tally[0], atomicLoad(&group_hits));
        atomicAdd(&tally[1], atomicLoad(&group_sum));
    }
}
