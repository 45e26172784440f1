// Test kernel: the image lookup (shared/image_texture.wgsl) at coordinates given by the host, so
// tests/suite/gltf.rs can check it against src/cpu/image_texture.rs. Binds only the scene's texel
// buffer (group 0, binding 7) and its own input and output.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/instrument.wgsl"

// xy: the coordinates; z: the material's image word (index and wraps) as bits.
@group(1) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

// Sizes the traversal's short stack (shared/bvh_stack.wgsl), which this kernel never uses.
override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(64)
fn image_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&probe_in) {
        return;
    }
    let q = probe_in[i];
    var m: Material;
    m.color = vec3<f32>(1.0);
    m.texture = TEXTURE_IMAGE;
    m.octaves = bitcast<u32>(q.z);
    probe_out[i] = vec4<f32>(image_albedo(m, q.xy), 0.0);
}
