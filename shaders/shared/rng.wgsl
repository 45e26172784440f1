// Counter-based random numbers; twin of src/rng.rs (bit-identical: integer-only hashing).
// pcg4d from Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020.

const PURPOSE_CAMERA: u32 = 0u;
const PURPOSE_SCATTER: u32 = 1u;
const PURPOSE_LIGHT: u32 = 2u;
const PURPOSE_ROULETTE: u32 = 3u;

fn pcg4d(key: vec4<u32>) -> vec4<u32> {
    var v = key * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> vec4<u32>(16u);
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// Top 24 bits to [0, 1): exact in f32, so identical everywhere.
fn to_unit(x: vec4<u32>) -> vec4<f32> {
    return vec4<f32>(x >> vec4<u32>(8u)) * (1.0 / 16777216.0);
}

fn uniform4(pixel: u32, sample: u32, bounce: u32, purpose: u32, seed: u32) -> vec4<f32> {
    return to_unit(pcg4d(vec4<u32>(pixel, sample, (bounce << 8u) | purpose, seed)));
}
