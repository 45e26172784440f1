// shade: scattering for the paths queued at one material kind (one entry point, and pipeline,
// per kind), or for every hit with a material switch (`shade`). Surviving paths go on the next
// bounce's ray queue; with --nee on, diffuse hits also put a shadow ray on the shadow queue for
// the shadow pass (or, when --roulette on ends the path, trace it here). Twin of the bounce body
// of src/cpu/integrator.rs. Rust: src/gpu/wavefront/shade.rs.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/path_start.wgsl"
#include "shared/instrument.wgsl"

override WORKGROUP_SIZE: u32 = 64u;
// --shadow-rays inline: a diffuse hit's shadow ray is traced here, not queued for the shadow pass.
override SHADOW_INLINE: bool = false;
// The bounce histogram's rows (queue_setup.wgsl's): inline shadow rays are counted in its shadow
// column, as queue_setup_shadow counts the queued ones.
override STATS_BOUNCES: u32 = 64u;

// `kind`: the material kind this pass shades, PATTERN_KIND + p for costly pattern p's queue
// (--shade per-texture: texture kind TEXTURE_NOISE + p; its pipeline compiled with that texture
// kind alone), or NO_KIND to shade whatever was hit.
const NO_KIND: u32 = 0xffffffffu;
const PATTERN_KIND: u32 = 0x100u;

fn shade_path(i: u32, kind: u32, pass_id: u32) {
    bvh_stack_lane(i);
    var q = QUEUE_MATERIAL_0;
    if kind >= PATTERN_KIND && kind != NO_KIND {
        q = QUEUE_PATTERN_0 + kind - PATTERN_KIND;
    } else if kind != NO_KIND {
        q += kind;
    }
    let slot = queued_slot(q, i);
    // Scan position: the shade passes' queues laid end to end (the pattern queues take atomic
    // appends only, which need none).
    var position = i;
    if q < QUEUE_PATTERN_0 {
        position += atomicLoad(&counters[COUNTER_SHADE_BASE + q - QUEUE_MATERIAL_0]);
    }
    if slot == DEAD || launched_past_done() {
        return;
    }
    let bounce = path_bounce(slot);
    // xyz: the ray; w: the hit's distance and primitive (intersect). A camera ray made in place
    // is made again here: only its hit is stored.
    var o: vec4<f32>;
    var d: vec4<f32>;
    if CAMERA_IN_PLACE && bounce == 0u {
        let camera = sample_camera_ray(slot_index(slot));
        o = vec4<f32>(camera.origin, path_origin[slot].w);
        d = vec4<f32>(camera.dir, path_dir[slot].w);
    } else {
        o = path_origin[slot];
        d = path_dir[slot];
    }
    let prim_slot = bitcast<u32>(d.w);
    if prim_slot == DEAD {
        return; // only without compaction
    }
    let prim = primitive(prim_slot);
    let material = materials[prim.material];
    if kind < PATTERN_KIND && material.kind != kind {
        return; // only without compaction
    }
    instrument(pass_id);
    let state = path_throughput_at(slot, bounce);
    let throughput = state.xyz;
    let ray = Ray(o.xyz, d.xyz);
    let sp = surface_point(prim, ray, o.w);
    let p = sp.p;
    if material_is(material.kind, MATERIAL_EMISSIVE) {
        // MIS-weighted when the previous hit sampled the lights (state.w: its bounce density).
        var w = 1.0;
        if state.w > 0.0 {
            w = emission_weight(prim_slot, ray.origin, p, ray.dir, o.w, state.w);
        }
        let emitted = vec4<f32>(throughput * material.color * w, 0.0);
        path_dir[slot].w = bitcast<f32>(DEAD);
        retire(slot, position);
        finish_path(slot, bounce, path_radiance(slot, bounce) + emitted, COUNTER_REFILLED_SHADE);
        return;
    }
    let outward = outward_normal(prim, p);
    let front_face = dot(ray.dir, outward) < 0.0;
    let normal = select(-outward, outward, front_face);
    let u = uniform4(slot_pixel(slot), slot_sample(slot), bounce, PURPOSE_SCATTER, frame.seed);
    let uv = surface_texture_uv(material, prim_slot, prim, p);
    let s = scatter(material, ray, texture_point(p), uv, normal, front_face, u);
    // The book's depth limit: a path still going after max_depth rays contributes nothing.
    if !s.ok || bounce + 1u >= frame.max_depth {
        if s.ok {
            count_failure(FAILURE_DEPTH_CUT);
        }
        path_dir[slot].w = bitcast<f32>(DEAD);
        retire(slot, position);
        finish_path(slot, bounce, path_radiance(slot, bounce), COUNTER_REFILLED_SHADE);
        return;
    }
    let next_throughput = throughput * s.attenuation;
    // Russian roulette: after the scatter, before the next ray, as on the CPU (a path at its last
    // bounce has ended above, as a depth cut).
    var rr = Survivor(true, next_throughput);
    if ROULETTE {
        let u_rr = uniform4(slot_pixel(slot), slot_sample(slot), bounce, PURPOSE_ROULETTE, frame.seed).x;
        rr = roulette(next_throughput, bounce, u_rr);
    }
    // Both rays leave to the side the normal faces: the shadow ray starts here too.
    let origin = spawn_origin(sp, outward, s.dir);
    // Direct light at diffuse hits, when the ray it stands in for is within the depth limit
    // (which also means this path goes on, unless the roulette ends it, so path_origin below is
    // the shadow ray's origin).
    let lights_sampled = NEE && material_is(material.kind, MATERIAL_LAMBERTIAN)
        && bounce + 2u <= frame.max_depth;
    var bsdf_pdf = 0.0;
    var shadow_queued = false;
    // What a shadow ray traced here adds (the roulette ended the path, below).
    var shadow_add = vec4<f32>(0.0);
    if lights_sampled {
        bsdf_pdf = diffuse_pdf(dot(normal, s.dir));
        let u_light = uniform4(slot_pixel(slot), slot_sample(slot), bounce, PURPOSE_LIGHT, frame.seed);
        let shadow = next_event(p, normal, u_light);
        if shadow.ok && rr.ok && !SHADOW_INLINE {
            shadow_ray[slot] = vec4<f32>(shadow.ray.dir, shadow.t_max);
            // w: the light's slot + 1 (0: no shadow ray pending), as bits.
            shadow_weight[slot] = vec4<f32>(next_throughput * shadow.weight, bitcast<f32>(shadow.light + 1u));
            enqueue_shadow(slot);
            shadow_queued = true;
        } else if shadow.ok {
            // Inline, or the roulette ends the path (its slot leaves every queue here): the
            // shadow ray is traced now, as the shadow pass would trace it (same ray, weight and
            // counters; its steps counted as the shadow pass's traversal).
            if SHADOW_INLINE && rr.ok {
                let row = min(bounce, STATS_BOUNCES - 1u);
                count_one(COUNTER_STATS + row * QUEUE_COUNT + QUEUE_SHADOW);
            }
            instrument_traversal(PASS_SHADOW_TRAVERSE);
            let ray_s = Ray(origin, shadow.ray.dir);
            shadow_add = vec4<f32>(0.0, 0.0, 0.0, 1.0); // one more ray traced
            if shadow_unblocked(ray_s, shadow.t_max, shadow.light, prim_slot) {
                shadow_add += vec4<f32>(next_throughput * shadow.weight, 0.0);
            }
        }
    }
    if !rr.ok {
        path_dir[slot].w = bitcast<f32>(DEAD);
        retire(slot, position);
        finish_path(slot, bounce, path_radiance(slot, bounce) + shadow_add, COUNTER_REFILLED_SHADE);
        return;
    }
    path_origin[slot] = vec4<f32>(origin, 0.0);
    // w: the primitive the ray leaves, for the self-hit counters of intersect and shadow.
    path_dir[slot] = vec4<f32>(s.dir, bitcast<f32>(prim_slot));
    path_throughput[slot] = vec4<f32>(rr.throughput, bsdf_pdf);
    if bounce == 0u {
        radiance[slot] = vec4<f32>(0.0); // the first write of the path's radiance (generate's none)
        if REGENERATE && CAMERA_IN_PLACE {
            count_one(COUNTER_FIRST_CONTINUING);
        }
    }
    if SHADOW_INLINE && shadow_add.w != 0.0 {
        // The shadow ray traced above: what the shadow pass would add to the radiance, added
        // here (from bounce 0 onto the first radiance just written).
        radiance[slot] = path_radiance(slot, bounce) + shadow_add;
    }
    if REGENERATE {
        path_sample[slot].y = bounce + 1u;
    }
    // The next iteration's ray queue (iterations and bounces coincide only in waves).
    enqueue_ray(slot, position, shadow_queued, bounce == 0u);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_lambertian(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, MATERIAL_LAMBERTIAN, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_metal(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, MATERIAL_METAL, PASS_SHADE_METAL);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_dielectric(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, MATERIAL_DIELECTRIC, PASS_SHADE_DIELECTRIC);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_emissive(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, MATERIAL_EMISSIVE, PASS_SHADE_EMISSIVE);
}

// The patterns' passes (--shade per-texture), counted with the lambertian pass by --instrument.
@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_noise(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 0u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_marble(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 1u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_wood(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 2u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_ridged(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 3u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_warp(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 4u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_cellular(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 5u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_crackle(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 6u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_value(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, PATTERN_KIND + 7u, PASS_SHADE_LAMBERTIAN);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn shade(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    shade_path(gid.x, NO_KIND, PASS_SHADE);
}

// --shade sorted: one pass over the material queues laid end to end (queue_setup_shade's scan
// positions: queue k starts at COUNTER_SHADE_BASE + k), so thread i shades the hit at position i
// with its queue's kind: a subgroup's lanes share a kind but where two queues meet.
@compute @workgroup_size(WORKGROUP_SIZE)
fn shade_sorted(@builtin(global_invocation_id) gid: vec3<u32>, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    var kind = 0u;
    for (var k = 1u; k < MATERIAL_KIND_COUNT; k++) {
        if gid.x >= atomicLoad(&counters[COUNTER_SHADE_BASE + k]) {
            kind = k;
        }
    }
    shade_path(gid.x - atomicLoad(&counters[COUNTER_SHADE_BASE + kind]), kind, PASS_SHADE);
}
