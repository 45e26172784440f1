// The megakernel: one thread traces whole paths for one pixel, every bounce and every material
// in one loop, as the seeds' CUDA and OpenGL ports did. Rust side: src/gpu/megakernel.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/film.wgsl"

// One dispatch's share of the render; twin of DispatchParams in src/layout.rs.
struct Dispatch {
    pixel_offset: u32,
    pixel_count: u32,
    sample_start: u32,
    sample_count: u32,
}

@group(1) @binding(0) var<storage, read_write> film: array<FilmPixel>;
@group(1) @binding(1) var<uniform> dispatch: Dispatch;

override WORKGROUP_SIZE: u32 = 64u;

// Twin of src/cpu/integrator.rs::trace_path.
fn trace_path(x: u32, y: u32, sample: u32) -> vec3<f32> {
    let pixel = y * frame.width + x;
    var ray = camera_ray(x, y, uniform4(pixel, sample, 0u, PURPOSE_CAMERA, frame.seed));
    var throughput = vec3<f32>(1.0);
    for (var bounce = 0u; bounce < frame.max_depth; bounce++) {
        let hit = closest_hit(ray, T_MIN);
        if hit.sphere == NO_HIT {
            return throughput * background(ray.dir);
        }
        let sphere = spheres[hit.sphere];
        let material = materials[sphere_material[hit.sphere]];
        if material.kind == MATERIAL_EMISSIVE {
            return throughput * material.color;
        }
        let p = ray.origin + ray.dir * hit.t;
        let outward = outward_normal(sphere, p);
        let front_face = dot(ray.dir, outward) < 0.0;
        let normal = select(-outward, outward, front_face);
        let u = uniform4(pixel, sample, bounce, PURPOSE_SCATTER, frame.seed);
        let s = scatter(material, ray, normal, front_face, u);
        if !s.ok {
            return vec3<f32>(0.0);
        }
        throughput *= s.attenuation;
        ray = Ray(p, s.dir);
    }
    return vec3<f32>(0.0);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn megakernel(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= dispatch.pixel_count {
        return;
    }
    let pixel = dispatch.pixel_offset + gid.x;
    let x = pixel % frame.width;
    let y = pixel / frame.width;
    // Sum this dispatch's samples locally, then add once: each pixel belongs to one thread per
    // dispatch and dispatches run in order, so accumulation is deterministic (no float atomics).
    var sum = vec3<f32>(0.0);
    var sum_sq = vec3<f32>(0.0);
    var dropped = 0.0;
    for (var i = 0u; i < dispatch.sample_count; i++) {
        let c = trace_path(x, y, dispatch.sample_start + i);
        if is_non_finite(c) {
            dropped += 1.0;
        } else {
            sum += c;
            sum_sq += c * c;
        }
    }
    var acc = film[pixel];
    acc.sum += vec4<f32>(sum, dropped);
    acc.sum_sq += vec4<f32>(sum_sq, 0.0);
    film[pixel] = acc;
}
