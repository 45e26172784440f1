// Textures: the albedo of a material at a surface point; twin of src/cpu/texture.rs.
// Noise is Perlin gradient noise whose lattice gradients come from hashing the lattice point
// (pcg4d) instead of the book's random tables: no extra bindings, and the same gradients as the
// CPU bit for bit. Its cost grows with `octaves`, the shading-cost knob of material_cost.json.

#include "shared/rng.wgsl"
#include "shared/kinds.wgsl"

const TEXTURE_SOLID: u32 = 0u;
const TEXTURE_CHECKER: u32 = 1u;
const TEXTURE_NOISE: u32 = 2u;
const TEXTURE_MARBLE: u32 = 3u;

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
// in: noise and marble's octave loops above all. 15: every kind (`--specialize none`).
override TEXTURE_KINDS: u32 = 15u;

fn texture_albedo(m: Material, p: vec3<f32>) -> vec3<f32> {
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
    return m.color;
}
