// Scattering by the book's materials; twin of src/cpu/material.rs.

// The kinds (MATERIAL_*) are listed in shared/kinds.wgsl, included below.

struct Material {
    // Albedo (or its tint for noise and marble, the even squares of a checker), or radiance for
    // an emitter.
    color: vec3<f32>,
    // Fuzz for metal, index of refraction for dielectric.
    param: f32,
    kind: u32,
    // TEXTURE_* in shared/texture.wgsl, with its octaves and scale.
    texture: u32,
    octaves: u32,
    scale: f32,
    // The odd squares of a checker.
    color2: vec3<f32>,
}

// Bit k is set when the scene has materials of kind k (PackedScene::material_kinds), set per
// pipeline so that only the scene's materials are compiled in. 15: every kind (`--specialize
// none`).
override MATERIAL_KINDS: u32 = 15u;

// Whether a material of kind `kind` is a `k`, in a scene with the kinds MATERIAL_KINDS: without
// emitters in the scene, the emission code (and its MIS weight) is dropped.
fn material_is(kind: u32, k: u32) -> bool {
    return kind_is(MATERIAL_KINDS, kind, k);
}

#include "shared/kinds.wgsl"
#include "shared/texture.wgsl"

struct Scatter {
    attenuation: vec3<f32>,
    dir: vec3<f32>,
    // False: the path is absorbed.
    ok: bool,
}

fn reflect_dir(v: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return v - n * (2.0 * dot(v, n));
}

fn refract_dir(uv: vec3<f32>, n: vec3<f32>, eta_ratio: f32) -> vec3<f32> {
    let cos_theta = min(dot(-uv, n), 1.0);
    let perp = (uv + n * cos_theta) * eta_ratio;
    let parallel = n * -sqrt(abs(1.0 - dot(perp, perp)));
    return perp + parallel;
}

// Schlick's approximation; (1 - cosine)^5 by multiplication, as the CPU twin, not pow().
fn reflectance(cosine: f32, eta_ratio: f32) -> f32 {
    var r0 = (1.0 - eta_ratio) / (1.0 + eta_ratio);
    r0 = r0 * r0;
    let t = 1.0 - cosine;
    let t2 = t * t;
    return r0 + (1.0 - r0) * (t2 * t2 * t);
}

// Pipeline constant: `--fresnel exact`.
override FRESNEL_EXACT: bool = false;

// The exact unpolarised Fresnel reflectance for incident cosine `cos_i` and eta_ratio =
// n_incident / n_transmitted; 1 under total internal reflection. Twin of fresnel_exact in
// src/cpu/material.rs.
fn fresnel_exact(cos_i: f32, eta_ratio: f32) -> f32 {
    let sin2_t = eta_ratio * eta_ratio * max(1.0 - cos_i * cos_i, 0.0);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let parallel = (cos_i - eta_ratio * cos_t) / (cos_i + eta_ratio * cos_t);
    let perpendicular = (eta_ratio * cos_i - cos_t) / (eta_ratio * cos_i + cos_t);
    return (parallel * parallel + perpendicular * perpendicular) / 2.0;
}

fn reflect_probability(cosine: f32, eta_ratio: f32) -> f32 {
    if FRESNEL_EXACT {
        return fresnel_exact(cosine, eta_ratio);
    }
    return reflectance(cosine, eta_ratio);
}

fn scatter_lambertian(m: Material, p: vec3<f32>, uv: vec2<f32>, normal: vec3<f32>, u: vec4<f32>) -> Scatter {
    var d = normal + unit_vector(u.x, u.y);
    // The book's near_zero guard.
    if all(abs(d) < vec3<f32>(1e-8)) {
        d = normal;
    }
    return Scatter(texture_albedo(m, p, uv), normalize(d), true);
}

fn scatter_metal(m: Material, ray: Ray, p: vec3<f32>, uv: vec2<f32>, normal: vec3<f32>, u: vec4<f32>) -> Scatter {
    let d = reflect_dir(ray.dir, normal) + unit_vector(u.x, u.y) * m.param;
    if dot(d, normal) <= 0.0 {
        return Scatter(vec3<f32>(0.0), vec3<f32>(0.0), false);
    }
    return Scatter(texture_albedo(m, p, uv), normalize(d), true);
}

fn scatter_dielectric(m: Material, ray: Ray, normal: vec3<f32>, front_face: bool, u: vec4<f32>) -> Scatter {
    var ri = m.param;
    if front_face {
        ri = 1.0 / m.param;
    }
    let cos_theta = min(dot(-ray.dir, normal), 1.0);
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    var d: vec3<f32>;
    if ri * sin_theta > 1.0 || reflect_probability(cos_theta, ri) > u.z {
        d = reflect_dir(ray.dir, normal);
    } else {
        d = refract_dir(ray.dir, normal, ri);
    }
    return Scatter(vec3<f32>(1.0), normalize(d), true);
}

// `p`: the hit point, where the solid textures are evaluated; `uv`: its texture coordinates
// (read by an image alone: surface_texture_uv). Never called for an emitter (its path ends
// at the hit), so the kinds that scatter are the scene's less emissive: a scene with one of them
// branches on no kind at all.
fn scatter(m: Material, ray: Ray, p: vec3<f32>, uv: vec2<f32>, normal: vec3<f32>, front_face: bool, u: vec4<f32>) -> Scatter {
    let scattering = MATERIAL_KINDS & ~(1u << MATERIAL_EMISSIVE);
    if kind_is(scattering, m.kind, MATERIAL_LAMBERTIAN) {
        return scatter_lambertian(m, p, uv, normal, u);
    }
    if kind_is(scattering, m.kind, MATERIAL_METAL) {
        return scatter_metal(m, ray, p, uv, normal, u);
    }
    if kind_is(scattering, m.kind, MATERIAL_DIELECTRIC) {
        return scatter_dielectric(m, ray, normal, front_face, u);
    }
    return Scatter(vec3<f32>(0.0), vec3<f32>(0.0), false);
}

// Pipeline constant: `--roulette on` (Russian roulette, pbrt-v4's rule).
override ROULETTE: bool = false;

// What Russian roulette left of a path: whether it goes on, and its throughput if so.
struct Survivor {
    ok: bool,
    throughput: vec3<f32>,
}

// pbrt-v4's Russian roulette at hit `bounce` (0: the camera ray's hit), given the throughput with
// this hit's attenuation in it and a uniform `u` (PURPOSE_ROULETTE): from the second hit on, a
// throughput whose largest component is below 1 ends the path with probability 1 - that
// component, and a survivor is divided by its survival probability. etaScale is 1: the book's
// dielectric does not scale radiance. Twin of roulette in src/cpu/integrator.rs.
fn roulette(throughput: vec3<f32>, bounce: u32, u: f32) -> Survivor {
    let largest = max(throughput.x, max(throughput.y, throughput.z));
    if bounce == 0u || !(largest < 1.0) {
        return Survivor(true, throughput);
    }
    let q = max(1.0 - largest, 0.0);
    if u < q {
        return Survivor(false, throughput);
    }
    return Survivor(true, throughput / (1.0 - q));
}
