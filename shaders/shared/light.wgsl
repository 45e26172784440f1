// Next-event estimation: a point sampled on an emitter and the shadow ray to it; twin of
// src/cpu/light.rs. A light is chosen from the alias table `lights` (uniformly, or by power), a
// point on it by area, or on a sphere seen from outside by the cone it subtends; emitters shine
// from both sides. Densities are per unit solid angle at the shading point, light choice
// included. The shadow ray and the diffuse bounce that may find the same light are combined by
// MIS (power heuristic). Needs the scene bindings (shared/scene.wgsl).

// Next-event estimation on, in a scene with lights (set per pipeline: off, its code is dropped).
override NEE: bool = false;
// --light-sampling solid-angle: spheres seen from outside sampled by the cone they subtend.
override LIGHT_SOLID_ANGLE: bool = true;
// --light-select power, in a scene whose lights have a positive total power.
override LIGHT_POWER: bool = true;

// One column of the alias table (LightEntry in src/layout.rs; src/light_table.rs builds it).
struct LightEntry {
    slot: u32,
    other: u32,
    threshold: f32,
}

struct LightSample {
    point: vec3<f32>,
    normal: vec3<f32>,
    pdf: f32,
    slot: u32,
}

struct ShadowRay {
    ray: Ray,
    // The light point's distance: unblocked when no primitive but `light` lies in (frame.t_min, t_max).
    t_max: f32,
    light: u32,
    // Light radiance × cos at the surface / π / solid-angle density × MIS weight: times
    // throughput and albedo it is the diffuse direct-light estimate.
    weight: vec3<f32>,
    // False: no light, or the sampled point cannot contribute.
    ok: bool,
}

// A sphere, in a scene that has spheres (PRIM_KINDS): without them the sphere code is dropped.
fn is_sphere(p: Primitive) -> bool {
    return prim_is(p.kind, PRIM_SPHERE);
}

// The slot of the light chosen by u0 (column) and u3 (keep its light or take its alias).
fn choose_light(u0: f32, u3: f32) -> u32 {
    let n = frame.light_count;
    var i = min(u32(u0 * f32(n)), n - 1u);
    if LIGHT_POWER && u3 >= lights[i].threshold {
        i = lights[i].other;
    }
    return lights[i].slot;
}

// Probability that choose_light picks `light`: 1/n, or its share of the scene's power.
fn light_pmf(light: Primitive) -> f32 {
    if LIGHT_POWER {
        let c = materials[light.material].color;
        let mean = (c.x + c.y + c.z) / 3.0;
        return mean * primitive_area(light) / frame.light_power;
    }
    return 1.0 / f32(frame.light_count);
}

// Solid-angle density at `x` of direction `dir` to `point` on `light` at squared distance
// `dist2`, as sample_light samples it.
fn light_pdf(light: Primitive, x: vec3<f32>, point: vec3<f32>, dir: vec3<f32>, dist2: f32) -> f32 {
    let pmf = light_pmf(light);
    if LIGHT_SOLID_ANGLE && is_sphere(light) {
        let c = sphere_cone(light, x);
        if c.ok {
            return pmf / cone_solid_angle(c);
        }
    }
    let cos_light = abs(dot(outward_normal(light, point), dir));
    return pmf / primitive_area(light) * dist2 / cos_light;
}

// A light (u.x, u.w) and a point on it (u.y, u.z) for the shading point `x`; needs lights.
fn sample_light(x: vec3<f32>, u: vec4<f32>) -> LightSample {
    let slot = choose_light(u.x, u.w);
    let light = primitive(slot);
    if LIGHT_SOLID_ANGLE && is_sphere(light) {
        let c = sphere_cone(light, x);
        if c.ok {
            let s = sample_cone(light, c, u.y, u.z);
            return LightSample(s[0], s[1], light_pmf(light) / cone_solid_angle(c), slot);
        }
    }
    let point = sample_point(light, u.y, u.z);
    let to = point - x;
    let dist2 = dot(to, to);
    let pdf = light_pdf(light, x, point, to / sqrt(dist2), dist2);
    return LightSample(point, outward_normal(light, point), pdf, slot);
}

// Power-heuristic weight of density `a` against `b`.
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

// MIS weight of emission from the light in `slot`, found from `origin` at distance `dist` along
// unit `dir` (at `point`) by a diffuse bounce whose density for `dir` was `bsdf_pdf`.
fn emission_weight(slot: u32, origin: vec3<f32>, point: vec3<f32>, dir: vec3<f32>, dist: f32, bsdf_pdf: f32) -> f32 {
    return power_heuristic(bsdf_pdf, light_pdf(primitive(slot), origin, point, dir, dist * dist));
}

fn next_event(p: vec3<f32>, normal: vec3<f32>, u: vec4<f32>) -> ShadowRay {
    let none = ShadowRay(Ray(p, normal), 0.0, NO_HIT, vec3<f32>(0.0), false);
    if frame.light_count == 0u {
        return none;
    }
    let l = sample_light(p, u);
    let to = l.point - p;
    let dist2 = dot(to, to);
    let dist = sqrt(dist2);
    if !(dist > 0.0) {
        return none;
    }
    let dir = to / dist;
    let cos_surface = dot(normal, dir);
    let facing = dot(l.normal, dir);
    if !(cos_surface > 0.0 && abs(facing) > 0.0 && l.pdf > 0.0 && l.pdf <= 3.4028235e38) {
        return none;
    }
    // The light's own surface, decided as closest_hit decides it: from outside a sphere the ray
    // meets the near side first, so a point facing away is hidden by the sphere.
    let light = primitive(l.slot);
    if is_sphere(light) && facing > 0.0 && sphere_cone(light, p).ok {
        return none;
    }
    let radiance = materials[light.material].color;
    let mis = power_heuristic(l.pdf, diffuse_pdf(cos_surface));
    let weight = radiance * (mis * cos_surface / (l.pdf * PI));
    return ShadowRay(Ray(p, dir), dist, l.slot, weight, true);
}
