// The scene bindings every GPU method shares (group 0); Rust side: src/gpu/scene_buffers.rs.

#include "shared/frame.wgsl"
#include "shared/ray.wgsl"
#include "shared/sampling.wgsl"
#include "shared/primitive.wgsl"
#include "shared/material.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> primitives: array<Primitive>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;
// The BVH in its layout's 16-byte units (shared/bvh.wgsl).
@group(0) @binding(3) var<storage, read> nodes: array<vec4<u32>>;
// The alias table of the emitting primitives (one unused entry when there are none:
// frame.light_count); shared/light.wgsl.
@group(0) @binding(4) var<storage, read> lights: array<LightEntry>;
// Self-hits and depth-cut paths (shared/offset.wgsl), read back once per render.
@group(0) @binding(5) var<storage, read_write> failures: array<atomic<u32>, 6>;
// Image textures (shared/image_texture.wgsl): texture coordinates per primitive slot and the
// texel buffer; one unused element each in a scene without image textures.
@group(0) @binding(6) var<storage, read> uvs: array<UvRecord>;
@group(0) @binding(7) var<storage, read> texels: array<u32>;
// Bindings 8..=13: the further bindings of the primitives and the nodes, and their loads.
#include "shared/scene_split.wgsl"

#include "shared/image_texture.wgsl"

#include "shared/offset.wgsl"

#include "shared/bvh.wgsl"
#include "shared/light.wgsl"
#include "shared/camera.wgsl"
#include "shared/background.wgsl"

// Whether a shadow ray leaving primitive `left` reaches the light in slot `light` within `t_max`.
// A blocker that is the primitive it left is counted as a shadow self-hit. One rule for the
// megakernels' NEE, the wavefront's shadow pass, and shade when the roulette ends a path.
fn shadow_unblocked(ray: Ray, t_max: f32, light: u32, left: u32) -> bool {
    let blocker = occluder(ray, frame.t_min, t_max, light);
    if blocker.prim == NO_HIT {
        return true;
    }
    if is_self_hit(left, blocker.prim, ray, blocker.t) {
        count_failure(FAILURE_SHADOW_SELF_HIT);
    }
    return false;
}

// Where the texture of a surface at `p` is looked up: the stress transform undone.
fn texture_point(p: vec3<f32>) -> vec3<f32> {
    return (p - frame.texture_origin) * frame.texture_inv_scale;
}

// The texture coordinates of the hit at `p` on primitive `slot`, where material `m` looks up an
// image (zero otherwise, never read): recomputed from the hit point, so nothing is stored for
// them, and compiled out of scenes without image textures.
fn surface_texture_uv(m: Material, slot: u32, prim: Primitive, p: vec3<f32>) -> vec2<f32> {
    if kind_is(TEXTURE_KINDS, m.texture, TEXTURE_IMAGE) {
        return surface_uv(slot, prim, p);
    }
    return vec2<f32>(0.0);
}
