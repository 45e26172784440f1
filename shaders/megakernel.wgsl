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

@group(1) @binding(0) var<storage, read_write> samples: array<vec4<f32>>;
@group(1) @binding(1) var<uniform> dispatch: Dispatch;

override WORKGROUP_SIZE: u32 = 64u;

// Twin of src/cpu/integrator.rs::trace_path: rgb radiance, w rays traced.
fn trace_path(x: u32, y: u32, sample: u32) -> vec4<f32> {
    let pixel = y * frame.width + x;
    var ray = camera_ray(x, y, uniform4(pixel, sample, 0u, PURPOSE_CAMERA, frame.seed));
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var rays = 0u;
    // When the previous hit sampled the lights: this ray's density under the diffuse bounce, for
    // the MIS weight of the emission it may find (0: no light sampling, full weight).
    var bsdf_pdf = 0.0;
    for (var bounce = 0u; bounce < frame.max_depth; bounce++) {
        instrument(PASS_MEGAKERNEL_BOUNCE);
        rays += 1u;
        let hit = closest_hit(ray, T_MIN);
        if hit.prim == NO_HIT {
            radiance += throughput * background(ray.dir);
            break;
        }
        let prim = primitives[hit.prim];
        let material = materials[prim.material];
        instrument(PASS_MEGAKERNEL_MATERIAL);
        // Lanes active inside each material's branch: the divergence the wavefront removes.
        switch material.kind {
            case MATERIAL_LAMBERTIAN: { instrument(PASS_MEGAKERNEL_LAMBERTIAN); }
            case MATERIAL_METAL: { instrument(PASS_MEGAKERNEL_METAL); }
            case MATERIAL_DIELECTRIC: { instrument(PASS_MEGAKERNEL_DIELECTRIC); }
            default: { instrument(PASS_MEGAKERNEL_EMISSIVE); }
        }
        let p = ray.origin + ray.dir * hit.t;
        if material.kind == MATERIAL_EMISSIVE {
            var w = 1.0;
            if bsdf_pdf > 0.0 {
                w = emission_weight(hit.prim, p, ray.dir, hit.t, bsdf_pdf);
            }
            radiance += throughput * material.color * w;
            break;
        }
        let outward = outward_normal(prim, p);
        let front_face = dot(ray.dir, outward) < 0.0;
        let normal = select(-outward, outward, front_face);
        let u = uniform4(pixel, sample, bounce, PURPOSE_SCATTER, frame.seed);
        let s = scatter(material, ray, p, normal, front_face, u);
        if !s.ok {
            break;
        }
        // Direct light at diffuse hits, when the ray it stands in for is within the depth limit.
        let lights_sampled = NEE && material.kind == MATERIAL_LAMBERTIAN && bounce + 2u <= frame.max_depth;
        bsdf_pdf = 0.0;
        if lights_sampled {
            bsdf_pdf = diffuse_pdf(dot(normal, s.dir));
            let shadow = next_event(p, normal, uniform4(pixel, sample, bounce, PURPOSE_LIGHT, frame.seed));
            if shadow.ok {
                instrument(PASS_MEGAKERNEL_SHADOW);
                rays += 1u;
                if !occluded(shadow.ray, T_MIN, shadow.t_max) {
                    radiance += throughput * s.attenuation * shadow.weight;
                }
            }
        }
        throughput *= s.attenuation;
        ray = Ray(p, s.dir);
    }
    return vec4<f32>(radiance, f32(rays));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn megakernel(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= dispatch.pixel_count * dispatch.sample_count {
        return;
    }
    // Neighbouring threads take neighbouring pixels of the same sample: coherent camera rays.
    let pixel = dispatch.pixel_offset + i % dispatch.pixel_count;
    let sample = dispatch.sample_start + i / dispatch.pixel_count;
    samples[i] = trace_path(pixel % frame.width, pixel / frame.width, sample);
}
