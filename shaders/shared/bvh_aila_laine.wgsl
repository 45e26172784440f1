// Traversal of the Aila–Laine layout (src/bvh/aila_laine.rs); twin of src/cpu/bvh_aila_laine.rs.
// Node i is four units from unit 2 (after the header): per child (min, first), (max, count). A
// child's count word is 0 for an inner node (first: its index) or LEAF | primitives (first: the
// first slot). The stack holds child references, so a leaf is never fetched as a node.

const AL_LEAF: u32 = 0x80000000u;

fn traverse_aila_laine(ray: Ray, t_min: f32, t_max: f32, any_hit: bool, skip: u32) -> Hit {
    let inv = safe_inverse(ray.dir);
    var closest = t_max;
    var hit = Hit(0.0, NO_HIT);
    var stack_first: array<u32, BVH_STACK>;
    var stack_count: array<u32, BVH_STACK>;
    var top = 0u;
    // The root (inner node 0) first.
    var first = 0u;
    var count = 0u;
    loop {
        if count != 0u {
            instrument_step(TRAVERSE_LEAF);
            let end = first + (count & ~AL_LEAF);
            for (var slot = first; slot < end; slot++) {
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
            let u = 2u + 4u * first;
            let l0 = node_unit(u);
            let l1 = node_unit(u + 1u);
            let r0 = node_unit(u + 2u);
            let r1 = node_unit(u + 3u);
            let ta = hit_bounds(bitcast<vec3<f32>>(l0.xyz), bitcast<vec3<f32>>(l1.xyz), ray.origin, inv, t_min, closest);
            let tb = hit_bounds(bitcast<vec3<f32>>(r0.xyz), bitcast<vec3<f32>>(r1.xyz), ray.origin, inv, t_min, closest);
            if ta >= 0.0 && tb >= 0.0 {
                // Nearer child first; the farther waits on the stack.
                if ta <= tb {
                    stack_push2(&stack_first, &stack_count, top, r0.w, r1.w);
                    first = l0.w;
                    count = l1.w;
                } else {
                    stack_push2(&stack_first, &stack_count, top, l0.w, l1.w);
                    first = r0.w;
                    count = r1.w;
                }
                top++;
                continue;
            }
            if ta >= 0.0 {
                first = l0.w;
                count = l1.w;
                continue;
            }
            if tb >= 0.0 {
                first = r0.w;
                count = r1.w;
                continue;
            }
        }
        if top == 0u {
            break;
        }
        top--;
        let entry = stack_pop2(&stack_first, &stack_count, top);
        first = entry.x;
        count = entry.y;
    }
    return hit;
}
