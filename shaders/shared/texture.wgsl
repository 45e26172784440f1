// Textures: the albedo of a material at a surface point; twin of src/cpu/texture.rs.
// Noise is Perlin gradient noise whose lattice gradients come from hashing the lattice point
// (pcg4d) instead of the book's random tables: no extra bindings, and the same gradients as the
// CPU bit for bit. Its cost grows with `octaves`, the shading-cost knob of material_cost.json.
// The costly patterns (noise, marble and six more: scene::Pattern) each hash the 8 lattice
// corners around the point once per octave, so they cost about the same (rtiow-kinds-K).

#include "shared/rng.wgsl"
#include "shared/kinds.wgsl"

const TEXTURE_SOLID: u32 = 0u;
const TEXTURE_CHECKER: u32 = 1u;
const TEXTURE_NOISE: u32 = 2u;
const TEXTURE_MARBLE: u32 = 3u;
const TEXTURE_WOOD: u32 = 4u;
const TEXTURE_RIDGED: u32 = 5u;
const TEXTURE_WARP: u32 = 6u;
const TEXTURE_CELLULAR: u32 = 7u;
const TEXTURE_CRACKLE: u32 = 8u;
const TEXTURE_VALUE: u32 = 9u;
// An image at the surface's texture coordinates (shared/image_texture.wgsl).
const TEXTURE_IMAGE: u32 = 10u;

// A hash word's top 24 bits in [0, 1), exact in f32.
fn hash_unit(h: u32) -> f32 {
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// One of Perlin's 12 edge directions (improved noise), picked by the lattice point's hash.
fn lattice_gradient(i: vec3<i32>) -> vec3<f32> {
    let h = pcg4d(vec4<u32>(bitcast<vec3<u32>>(i), 0x6e6f6973u)).x % 12u;
    let a = select(1.0, -1.0, (h & 1u) != 0u);
    let b = select(1.0, -1.0, (h & 2u) != 0u);
    let axis = h >> 2u;
    if axis == 0u {
        return vec3<f32>(a, b, 0.0);
    }
    if axis == 1u {
        return vec3<f32>(a, 0.0, b);
    }
    return vec3<f32>(0.0, a, b);
}

// Gradient noise in about [-1, 1], Hermite-smoothed trilinear as the book's perlin_interp.
fn perlin(p: vec3<f32>) -> f32 {
    let cell = floor(p);
    let f = p - cell;
    let i = vec3<i32>(cell);
    let s = f * f * (3.0 - 2.0 * f);
    var accum = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let d = vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
        let df = vec3<f32>(d);
        let w = df * s + (1.0 - df) * (1.0 - s);
        accum += w.x * w.y * w.z * dot(lattice_gradient(i + vec3<i32>(d)), f - df);
    }
    return accum;
}

// Value noise in [-1, 1): a hashed value per lattice corner ("valu"), Hermite-smoothed trilinear.
fn value_noise(p: vec3<f32>) -> f32 {
    let cell = floor(p);
    let f = p - cell;
    let i = vec3<i32>(cell);
    let s = f * f * (3.0 - 2.0 * f);
    var accum = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let d = vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
        let df = vec3<f32>(d);
        let w = df * s + (1.0 - df) * (1.0 - s);
        let h = pcg4d(vec4<u32>(bitcast<vec3<u32>>(i + vec3<i32>(d)), 0x76616c75u)).x;
        accum += w.x * w.y * w.z * (2.0 * hash_unit(h) - 1.0);
    }
    return accum;
}

// Worley noise over the 8 cells nearest `p` (the 2x2x2 block around its closest lattice point),
// one feature point each ("cell"): the nearest and second-nearest squared distances.
fn worley(p: vec3<f32>) -> vec2<f32> {
    let i = vec3<i32>(floor(p - vec3<f32>(0.5)));
    var f = vec2<f32>(1e9);
    for (var c = 0u; c < 8u; c++) {
        let cell = i + vec3<i32>(vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u));
        let h = pcg4d(vec4<u32>(bitcast<vec3<u32>>(cell), 0x63656c6cu));
        let v = vec3<f32>(cell) + vec3<f32>(hash_unit(h.x), hash_unit(h.y), hash_unit(h.z)) - p;
        let d2 = dot(v, v);
        if d2 < f.x {
            f = vec2<f32>(d2, f.x);
        } else if d2 < f.y {
            f.y = d2;
        }
    }
    return f;
}

// The book's turbulence: |sum of octaves|, each at twice the frequency and half the weight.
fn turbulence(p: vec3<f32>, octaves: u32) -> f32 {
    var accum = 0.0;
    var q = p;
    var weight = 1.0;
    for (var o = 0u; o < octaves; o++) {
        accum += weight * perlin(q);
        weight *= 0.5;
        q *= 2.0;
    }
    return abs(accum);
}

// Bit k is set when a textured material of the scene (lambertian, metal) has texture kind k
// (PackedScene::texture_kinds), set per pipeline so that only the scene's textures are compiled
// in: the patterns' octave loops above all, and the image lookup with its bindings. 2047: every
// kind (`--specialize none`).
override TEXTURE_KINDS: u32 = 2047u;

// The six patterns beyond noise and marble, in [0, 1] (twin of `pattern` in src/cpu/texture.rs).
fn pattern_wood(p: vec3<f32>, scale: f32, octaves: u32) -> f32 {
    let q = p * scale;
    let r = sqrt(q.x * q.x + q.z * q.z) + 2.0 * turbulence(q, octaves);
    return 0.3 + 0.7 * (0.5 * (1.0 + sin(6.2831855 * r)));
}

fn pattern_ridged(p: vec3<f32>, scale: f32, octaves: u32) -> f32 {
    var accum = 0.0;
    var q = p * scale;
    var weight = 0.5;
    for (var o = 0u; o < octaves; o++) {
        let ridge = 1.0 - abs(perlin(q));
        accum += weight * ridge * ridge;
        weight *= 0.5;
        q *= 2.0;
    }
    return clamp(accum, 0.0, 1.0);
}

fn pattern_warp(p: vec3<f32>, scale: f32, octaves: u32) -> f32 {
    var accum = 0.0;
    var q = p * scale;
    var weight = 1.0;
    for (var o = 0u; o < octaves; o++) {
        let n = perlin(q);
        accum += weight * n;
        weight *= 0.5;
        q = q * 2.0 + vec3<f32>(n, -n, n) * 1.7;
    }
    return clamp(0.5 + accum, 0.0, 1.0);
}

// Cellular (F1) or crackle (F2 - F1).
fn pattern_worley(p: vec3<f32>, scale: f32, octaves: u32, crackle: bool) -> f32 {
    var accum = 0.0;
    var q = p * scale;
    var weight = 1.0;
    for (var o = 0u; o < octaves; o++) {
        let f = worley(q);
        var v = sqrt(f.x);
        if crackle {
            v = sqrt(f.y) - sqrt(f.x);
        }
        accum += weight * v;
        weight *= 0.5;
        q *= 2.0;
    }
    return clamp(accum, 0.0, 1.0);
}

fn pattern_value(p: vec3<f32>, scale: f32, octaves: u32) -> f32 {
    var accum = 0.0;
    var q = p * scale;
    var weight = 0.5;
    for (var o = 0u; o < octaves; o++) {
        accum += weight * value_noise(q);
        weight *= 0.5;
        q *= 2.0;
    }
    return clamp(0.5 + accum, 0.0, 1.0);
}

// `p`: where the solid textures are evaluated; `uv`: the surface's texture coordinates (only
// computed, and only read, for an image).
fn texture_albedo(m: Material, p: vec3<f32>, uv: vec2<f32>) -> vec3<f32> {
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_CHECKER) {
        let c = floor(p / m.scale);
        let parity = (i32(c.x) + i32(c.y) + i32(c.z)) & 1;
        return select(m.color, m.color2, parity != 0);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_NOISE) {
        return m.color * turbulence(p * m.scale, m.octaves);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_MARBLE) {
        return m.color * (0.5 * (1.0 + sin(m.scale * p.z + 10.0 * turbulence(p, m.octaves))));
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_WOOD) {
        return m.color * pattern_wood(p, m.scale, m.octaves);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_RIDGED) {
        return m.color * pattern_ridged(p, m.scale, m.octaves);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_WARP) {
        return m.color * pattern_warp(p, m.scale, m.octaves);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_CELLULAR) {
        return m.color * pattern_worley(p, m.scale, m.octaves, false);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_CRACKLE) {
        return m.color * pattern_worley(p, m.scale, m.octaves, true);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_VALUE) {
        return m.color * pattern_value(p, m.scale, m.octaves);
    }
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_IMAGE) {
        return image_albedo(m, uv);
    }
    return m.color;
}
