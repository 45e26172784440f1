// Test kernel: evaluates the shared RNG for keys given by the host, so tests/gpu_rng.rs can check
// bit identity with src/rng.rs.

#include "shared/rng.wgsl"

@group(0) @binding(0) var<storage, read> keys: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> hashes: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> unit: array<vec4<f32>>;

@compute @workgroup_size(64)
fn rng_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&keys) {
        return;
    }
    let k = keys[i];
    hashes[i] = pcg4d(k);
    unit[i] = uniform4(k.x, k.y, k.z >> 8u, k.z & 0xffu, k.w);
}
