// Closest-hit and any-hit BVH traversal; twin of src/cpu/bvh.rs (same stack, same child order).
// Needs `nodes` and `primitives` bound (shared/scene.wgsl), and instrument.wgsl included by the
// entry (its step counters; the caller names the traversal with instrument_traversal).

// Matches bvh::MAX_DEPTH: the builder never makes a deeper tree.
const BVH_STACK: u32 = 64u;

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

// Entry distance into the box if the ray enters before t_max, else -1.
fn hit_box(n: BvhNode, o: vec3<f32>, inv: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    let t1 = (n.min - o) * inv;
    let t2 = (n.max - o) * inv;
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

// The one traversal loop: nearer child first, the farther on the stack. `any_hit` returns the
// first hit found in (t_min, t_max) instead of the nearest; the primitive in slot `skip` is not
// tested.
fn traverse(ray: Ray, t_min: f32, t_max: f32, any_hit: bool, skip: u32) -> Hit {
    let inv = safe_inverse(ray.dir);
    var closest = t_max;
    var hit = Hit(0.0, NO_HIT);
    var stack: array<u32, BVH_STACK>;
    var top = 0u;
    var current = 0u;
    if hit_box(nodes[0], ray.origin, inv, t_min, closest) < 0.0 {
        return hit;
    }
    loop {
        let n = nodes[current];
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
            let ta = hit_box(nodes[a], ray.origin, inv, t_min, closest);
            let tb = hit_box(nodes[b], ray.origin, inv, t_min, closest);
            if ta >= 0.0 && tb >= 0.0 {
                // Nearer child first; the farther waits on the stack.
                if ta <= tb {
                    stack[top] = b;
                    current = a;
                } else {
                    stack[top] = a;
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
        current = stack[top];
    }
    return hit;
}
