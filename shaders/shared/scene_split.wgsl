// The primitives and the BVH nodes split over up to four storage bindings each, where one
// binding cannot hold them (src/gpu/scene_split.rs: lavapipe binds at most 128 MiB, 10⁷
// triangles take 458 MiB of primitives). Element i lives in binding i / *_PER_BINDING at
// i % *_PER_BINDING; `primitives` and `nodes` (shared/scene.wgsl) are the first bindings.
// Four, not more: lavapipe allows 32 storage buffers a stage and the wavefront's passes bind
// 14 of their own. With one binding (every scene that fits one) the loads are the plain array
// loads: the constants are pipeline constants, so the driver drops the rest.

@group(0) @binding(8) var<storage, read> primitives_1: array<Primitive>;
@group(0) @binding(9) var<storage, read> primitives_2: array<Primitive>;
@group(0) @binding(10) var<storage, read> primitives_3: array<Primitive>;
@group(0) @binding(11) var<storage, read> nodes_1: array<vec4<u32>>;
@group(0) @binding(12) var<storage, read> nodes_2: array<vec4<u32>>;
@group(0) @binding(13) var<storage, read> nodes_3: array<vec4<u32>>;

// Bindings the primitives take (1..=4) and primitives in each but the last.
override PRIM_BINDINGS: u32 = 1u;
override PRIM_PER_BINDING: u32 = 0xffffffffu;
// The same for the BVH's 16-byte units.
override NODE_BINDINGS: u32 = 1u;
override NODE_PER_BINDING: u32 = 0xffffffffu;

// The primitive in slot `slot`.
fn primitive(slot: u32) -> Primitive {
    if PRIM_BINDINGS == 1u {
        return primitives[slot];
    }
    let b = slot / PRIM_PER_BINDING;
    let i = slot - b * PRIM_PER_BINDING;
    switch b {
        case 0u: {
            return primitives[i];
        }
        case 1u: {
            return primitives_1[i];
        }
        case 2u: {
            return primitives_2[i];
        }
        default: {
            return primitives_3[i];
        }
    }
}

// Unit `u` of the BVH's nodes (shared/bvh.wgsl).
fn node_unit(u: u32) -> vec4<u32> {
    if NODE_BINDINGS == 1u {
        return nodes[u];
    }
    let b = u / NODE_PER_BINDING;
    let i = u - b * NODE_PER_BINDING;
    switch b {
        case 0u: {
            return nodes[i];
        }
        case 1u: {
            return nodes_1[i];
        }
        case 2u: {
            return nodes_2[i];
        }
        default: {
            return nodes_3[i];
        }
    }
}
