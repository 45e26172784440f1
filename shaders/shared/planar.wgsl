// Ray–quad and ray–triangle intersection; twin of src/cpu/planar.rs. A plane hit, then the hit's
// coordinates (α, β) in the frame of the edges b and c: a quad keeps both in [0, 1], a triangle
// keeps both ≥ 0 with α + β ≤ 1.

// Rays closer to parallel than this (cosine to the normal, squared) miss: PARALLEL_COS2 in Rust.
const PARALLEL_COS2: f32 = 1e-16;

// Distance to the hit in (t_min, t_max), or -1 for none.
fn hit_planar(kind: u32, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, ray: Ray, t_min: f32, t_max: f32) -> f32 {
    let n = cross(b, c);
    let nn = dot(n, n);
    let denom = dot(n, ray.dir);
    if denom * denom <= PARALLEL_COS2 * nn {
        return -1.0;
    }
    let t = dot(n, a - ray.origin) / denom;
    if !(t > t_min && t < t_max) {
        return -1.0;
    }
    let h = ray.origin + ray.dir * t - a;
    let w = n / nn;
    let alpha = dot(w, cross(h, c));
    let beta = dot(w, cross(b, h));
    var inside: bool;
    if prim_is(kind, PRIM_QUAD) {
        inside = alpha >= 0.0 && alpha <= 1.0 && beta >= 0.0 && beta <= 1.0;
    } else {
        inside = alpha >= 0.0 && beta >= 0.0 && alpha + beta <= 1.0;
    }
    if inside {
        return t;
    }
    return -1.0;
}

fn planar_normal(p: Primitive) -> vec3<f32> {
    return normalize(cross(p.b, p.c));
}
