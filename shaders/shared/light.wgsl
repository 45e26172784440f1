// Next-event estimation: a point sampled on an emitter and the shadow ray to it; twin of
// src/cpu/light.rs. A light is picked uniformly from `lights`, a point on it uniformly by area;
// emitters shine from both sides. The shadow ray and the diffuse bounce that may find the same
// light are combined by MIS (power heuristic). Needs the scene bindings (shared/scene.wgsl).

// Next-event estimation on, in a scene with lights (set per pipeline: off, its code is dropped).
override NEE: bool = false;

// A shadow ray stops this fraction of the distance short of the light (SHADOW_SHORTEN in Rust).
const SHADOW_SHORTEN: f32 = 1e-4;

struct ShadowRay {
    ray: Ray,
    // Unblocked when nothing is hit in (T_MIN, t_max).
    t_max: f32,
    // Light radiance × cos at the surface / π / solid-angle density × MIS weight: times
    // throughput and albedo it is the diffuse direct-light estimate.
    weight: vec3<f32>,
    // False: no light, or the sampled point cannot contribute.
    ok: bool,
}

// The area density of a point sampled on `light`: uniform light choice, then uniform by area.
fn light_pdf_area(light: Primitive) -> f32 {
    return 1.0 / (f32(frame.light_count) * primitive_area(light));
}

// Power-heuristic weight of density `a` against `b` (both times the same positive factor).
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 > 0.0 {
        return a2 / (a2 + b2);
    }
    return 0.0;
}

// The cosine-weighted diffuse bounce's density at cosine `cos` to the normal.
fn diffuse_pdf(cos: f32) -> f32 {
    return max(cos, 0.0) / PI;
}

// MIS weight of emission from the light in `slot`, found at distance `dist` along unit `dir` by
// a diffuse bounce whose density for `dir` was `bsdf_pdf`.
fn emission_weight(slot: u32, point: vec3<f32>, dir: vec3<f32>, dist: f32, bsdf_pdf: f32) -> f32 {
    let light = primitives[slot];
    let cos_light = abs(dot(outward_normal(light, point), dir));
    return power_heuristic(bsdf_pdf * cos_light, light_pdf_area(light) * dist * dist);
}

fn next_event(p: vec3<f32>, normal: vec3<f32>, u: vec4<f32>) -> ShadowRay {
    let none = ShadowRay(Ray(p, normal), 0.0, vec3<f32>(0.0), false);
    let n = frame.light_count;
    if n == 0u {
        return none;
    }
    let slot = lights[min(u32(u.x * f32(n)), n - 1u)];
    let light = primitives[slot];
    let point = sample_point(light, u.y, u.z);
    let light_normal = outward_normal(light, point);
    let pdf_area = light_pdf_area(light);
    let to = point - p;
    let dist2 = dot(to, to);
    let dist = sqrt(dist2);
    if !(dist > 0.0) {
        return none;
    }
    let dir = to / dist;
    let cos_surface = dot(normal, dir);
    let cos_light = abs(dot(light_normal, dir));
    if !(cos_surface > 0.0 && cos_light > 0.0) {
        return none;
    }
    let radiance = materials[light.material].color;
    let mis = power_heuristic(pdf_area * dist2, diffuse_pdf(cos_surface) * cos_light);
    let weight = radiance * (mis * cos_surface * cos_light / (dist2 * pdf_area * PI));
    return ShadowRay(Ray(p, dir), dist * (1.0 - SHADOW_SHORTEN), weight, true);
}
