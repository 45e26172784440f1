// Traversal of the compressed 8-wide layout (src/bvh/wide.rs); twin of src/cpu/bvh_wide.rs.
// Node i is five units from unit 2 (after the header): (p, e bytes | imask << 24),
// (child_base, prim_base, meta 0-3, meta 4-7), then the quantized bounds, a byte per slot:
// lo x, lo y | lo z, hi x | hi y, hi z. A stack of node groups (first inner child, hit inner
// children in bits 24..31 over the parent's imask), the nearest child by the highest bit; the
// hit leaves' primitives in slot order (Ylitie et al. 2017; tinybvh's traverse_cwbvh.cl).

// Byte `slot` of the eight in (a, b): slots 0-3 in a, 4-7 in b.
fn wide_byte(a: u32, b: u32, slot: u32) -> u32 {
    return (select(a, b, slot >= 4u) >> (8u * (slot & 3u))) & 0xffu;
}

// The node's children the ray enters in (t_min, t_max): an inner child as bit
// 24 + (slot ^ octinv), a leaf as one bit per primitive from its offset. Bounds dequantize to
// p + q·2^(e−127) in f32 (exact product, so fused or not it rounds as the CPU's).
fn wide_hit_children(n0: vec4<u32>, n1: vec4<u32>, n2: vec4<u32>, n3: vec4<u32>, n4: vec4<u32>, o: vec3<f32>, inv: vec3<f32>, t_min: f32, t_max: f32, octinv: u32) -> u32 {
    let p = bitcast<vec3<f32>>(n0.xyz);
    let e = vec3<u32>(n0.w & 0xffu, (n0.w >> 8u) & 0xffu, (n0.w >> 16u) & 0xffu);
    let scale = bitcast<vec3<f32>>(e << vec3<u32>(23u));
    let imask = n0.w >> 24u;
    var hits = 0u;
    for (var slot = 0u; slot < 8u; slot++) {
        let info = wide_byte(n1.z, n1.w, slot);
        if info == 0u {
            continue;
        }
        let lo = vec3<f32>(vec3<u32>(wide_byte(n2.x, n2.y, slot), wide_byte(n2.z, n2.w, slot), wide_byte(n3.x, n3.y, slot)));
        let hi = vec3<f32>(vec3<u32>(wide_byte(n3.z, n3.w, slot), wide_byte(n4.x, n4.y, slot), wide_byte(n4.z, n4.w, slot)));
        if hit_bounds(p + lo * scale, p + hi * scale, o, inv, t_min, t_max) >= 0.0 {
            let at = select(info & 31u, 24u + (slot ^ octinv), ((imask >> slot) & 1u) == 1u);
            hits |= (info >> 5u) << at;
        }
    }
    return hits;
}

fn traverse_wide(ray: Ray, t_min: f32, t_max: f32, any_hit: bool, skip: u32) -> Hit {
    let inv = safe_inverse(ray.dir);
    let d = ray.dir;
    let octinv = 7u - (select(0u, 4u, d.x < 0.0) | select(0u, 2u, d.y < 0.0) | select(0u, 1u, d.z < 0.0));
    var closest = t_max;
    var hit = Hit(0.0, NO_HIT);
    var stack_base: array<u32, BVH_STACK>;
    var stack_hits: array<u32, BVH_STACK>;
    var top = 0u;
    // The root alone.
    var group_base = 0u;
    var group_hits = 0x80000000u;
    loop {
        if group_hits > 0x00ffffffu {
            let bit = firstLeadingBit(group_hits);
            let imask = group_hits & 0xffu;
            let base = group_base;
            group_hits &= ~(1u << bit);
            if group_hits > 0x00ffffffu {
                stack_push2(&stack_base, &stack_hits, top, base, group_hits);
                top++;
            }
            let child_slot = (bit - 24u) ^ octinv;
            let u = 2u + 5u * (base + countOneBits(imask & ((1u << child_slot) - 1u)));
            instrument_step(TRAVERSE_INNER);
            let n0 = node_unit(u);
            let n1 = node_unit(u + 1u);
            let hits = wide_hit_children(n0, n1, node_unit(u + 2u), node_unit(u + 3u), node_unit(u + 4u), ray.origin, inv, t_min, closest, octinv);
            group_base = n1.x;
            group_hits = (hits & 0xff000000u) | (n0.w >> 24u);
            var prims = hits & 0x00ffffffu;
            if prims != 0u {
                instrument_step(TRAVERSE_LEAF);
            }
            while prims != 0u {
                let slot = n1.y + firstTrailingBit(prims);
                prims &= prims - 1u;
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
        }
        if group_hits <= 0x00ffffffu {
            if top == 0u {
                break;
            }
            top--;
            let entry = stack_pop2(&stack_base, &stack_hits, top);
            group_base = entry.x;
            group_hits = entry.y;
        }
    }
    return hit;
}
