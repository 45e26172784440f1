// Closest-hit and any-hit BVH traversal; twin of src/cpu/bvh.rs (same stack, same child order).
// Needs `nodes` and `primitives` bound (shared/scene.wgsl), and instrument.wgsl included by the
// entry (its step counters; the caller names the traversal with instrument_traversal).
// `nodes` is the layout's words in 16-byte units (bvh::SceneBvh::gpu_words): the binary layout
// here, the others in bvh_aila_laine.wgsl and bvh_wide.wgsl, chosen by BVH_LAYOUT.

#include "shared/bvh_stack.wgsl"
#include "shared/bvh_aila_laine.wgsl"
#include "shared/bvh_wide.wgsl"

// Matches bvh::MAX_DEPTH and bvh::wide::MAX_DEPTH: the builders never make a deeper tree.
const BVH_STACK: u32 = 64u;

// `--bvh` (bvh::BvhLayout::constant): 0 binary, 1 aila-laine, 2 wide. A pipeline constant, so
// the driver compiles only the layout's loop.
override BVH_LAYOUT: u32 = 0u;

struct BvhNode {
    min: vec3<f32>,
    left_or_first: u32,
    max: vec3<f32>,
    count: u32,
}

struct Hit {
    t: f32,
    // Primitive slot, or 0xffffffff for a miss.
    prim: u32,
}

const NO_HIT: u32 = 0xffffffffu;

fn safe_inverse(d: vec3<f32>) -> vec3<f32> {
    let tiny = 1e-20;
    let s = select(vec3<f32>(tiny), vec3<f32>(-tiny), d < vec3<f32>(0.0));
    return 1.0 / select(d, s, abs(d) < vec3<f32>(tiny));
}

// Binary node i: two units, (min, left_or_first) and (max, count).
fn bvh_node(i: u32) -> BvhNode {
    let a = node_unit(2u * i);
    let b = node_unit(2u * i + 1u);
    return BvhNode(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w);
}

// The scene's box: the binary root's, or the other layouts' header in the same two units.
fn bvh_root_min() -> vec3<f32> {
    return bitcast<vec3<f32>>(node_unit(0u).xyz);
}

fn bvh_root_max() -> vec3<f32> {
    return bitcast<vec3<f32>>(node_unit(1u).xyz);
}

// Entry distance into the box if the ray enters before t_max, else -1.
fn hit_box(n: BvhNode, o: vec3<f32>, inv: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    return hit_bounds(n.min, n.max, o, inv, t_min, t_max);
}

// Entry distance into the box (lo, hi) if the ray enters before t_max, else -1: every layout's
// slab test, so a box containing another is entered by every ray that enters that one.
fn hit_bounds(lo_corner: vec3<f32>, hi_corner: vec3<f32>, o: vec3<f32>, inv: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    let t1 = (lo_corner - o) * inv;
    let t2 = (hi_corner - o) * inv;
    let lo = min(t1, t2);
    let hi = max(t1, t2);
    let near = max(max(max(lo.x, lo.y), lo.z), t_min);
    let far = min(min(min(hi.x, hi.y), hi.z), t_max);
    if near <= far {
        return near;
    }
    return -1.0;
}

// The nearest hit in (t_min, ∞).
fn closest_hit(ray: Ray, t_min: f32) -> Hit {
    return traverse(ray, t_min, 3.4028235e38, false, NO_HIT);
}

// Whether any primitive but the one in slot `skip` (the light a shadow ray aims at) lies on the
// ray in (t_min, t_max): the shadow-ray query.
fn occluded(ray: Ray, t_min: f32, t_max: f32, skip: u32) -> bool {
    return traverse(ray, t_min, t_max, true, skip).prim != NO_HIT;
}

// The first primitive but `skip` the traversal finds in (t_min, t_max), NO_HIT for none: the
// shadow-ray query when the occluder is counted (self-hits).
fn occluder(ray: Ray, t_min: f32, t_max: f32, skip: u32) -> Hit {
    return traverse(ray, t_min, t_max, true, skip);
}

// The query on the layout's loop. `any_hit` returns the first hit found in (t_min, t_max)
// instead of the nearest; the primitive in slot `skip` is not tested.
fn traverse(ray: Ray, t_min: f32, t_max: f32, any_hit: bool, skip: u32) -> Hit {
    if BVH_LAYOUT == 2u {
        return traverse_wide(ray, t_min, t_max, any_hit, skip);
    }
    if BVH_LAYOUT == 1u {
        return traverse_aila_laine(ray, t_min, t_max, any_hit, skip);
    }
    return traverse_binary(ray, t_min, t_max, any_hit, skip);
}

// The binary layout's loop: nearer child first, the farther on the stack.
fn traverse_binary(ray: Ray, t_min: f32, t_max: f32, any_hit: bool, skip: u32) -> Hit {
    let inv = safe_inverse(ray.dir);
    var closest = t_max;
    var hit = Hit(0.0, NO_HIT);
    var stack: array<u32, BVH_STACK>;
    var top = 0u;
    var current = 0u;
    if hit_box(bvh_node(0u), ray.origin, inv, t_min, closest) < 0.0 {
        return hit;
    }
    loop {
        let n = bvh_node(current);
        if n.count > 0u {
            instrument_step(TRAVERSE_LEAF);
            for (var slot = n.left_or_first; slot < n.left_or_first + n.count; slot++) {
                if slot == skip {
                    continue;
                }
                instrument_step(TRAVERSE_PRIMITIVE);
                let t = hit_primitive(slot, ray, t_min, closest);
                if t >= 0.0 {
                    closest = t;
                    hit = Hit(t, slot);
                    if any_hit {
                        return hit;
                    }
                }
            }
        } else {
            instrument_step(TRAVERSE_INNER);
            let a = current + 1u;
            let b = n.left_or_first;
            let ta = hit_box(bvh_node(a), ray.origin, inv, t_min, closest);
            let tb = hit_box(bvh_node(b), ray.origin, inv, t_min, closest);
            if ta >= 0.0 && tb >= 0.0 {
                // Nearer child first; the farther waits on the stack.
                if ta <= tb {
                    stack_push1(&stack, top, b);
                    current = a;
                } else {
                    stack_push1(&stack, top, a);
                    current = b;
                }
                top++;
                continue;
            }
            if ta >= 0.0 {
                current = a;
                continue;
            }
            if tb >= 0.0 {
                current = b;
                continue;
            }
        }
        if top == 0u {
            break;
        }
        top--;
        current = stack_pop1(&stack, top);
    }
    return hit;
}
