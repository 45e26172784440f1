// Coherence counters (issue 26), after the SIMD slots: per iteration bucket (the iteration is
// the bounce with waves, and counts refills when regenerating), per arriving subgroup: lanes,
// the distinct 64-byte lines of a 16-byte-per-slot path array its lanes touch, the
// half-perimeter in pixels of the box around its lanes' pixels, and the distinct direction
// octants of its rays (what --ray-sort orders by). Names: src/gpu/instrument.rs.
const COHERENCE_BASE: u32 = SIMD_SLOT_WORDS * PASS_SLOTS;
const COHERENCE_BUCKETS: u32 = 16u;
const COHERENCE_WORDS: u32 = 10u; // subgroups, lanes, lines, spread, octants; each (low, high)

// Distinct values of `v` over the active lanes: each round removes the smallest left.
fn subgroup_distinct(v: u32) -> u32 {
    var pending = true;
    var n = 0u;
    loop {
        let m = subgroupMin(select(0xffffffffu, v, pending));
        if m == 0xffffffffu {
            break;
        }
        n += 1u;
        if v == m {
            pending = false;
        }
    }
    return n;
}

// Iterations 0..7 each their own bucket, then one bucket per power of two (8..15, 16..31, …).
fn coherence_bucket(iteration: u32) -> u32 {
    if iteration < 8u {
        return iteration;
    }
    return min(8u + firstLeadingBit(iteration) - 3u, COHERENCE_BUCKETS - 1u);
}

fn instrument_coherence(slot: u32, d: vec3<f32>) {
    let lines = subgroup_distinct(slot / 4u);
    let octants = subgroup_distinct(select(0u, 1u, d.x < 0.0) | select(0u, 2u, d.y < 0.0) | select(0u, 4u, d.z < 0.0));
    let pixel = slot_pixel(slot);
    let x = pixel % frame.width;
    let y = pixel / frame.width;
    let spread = subgroupMax(x) - subgroupMin(x) + subgroupMax(y) - subgroupMin(y);
    let lanes = subgroupAdd(1u);
    let iteration = subgroupMax(current_bounce());
    if subgroupExclusiveAdd(1u) == 0u {
        let base = COHERENCE_BASE + COHERENCE_WORDS * coherence_bucket(iteration);
        add64(base, 1u);
        add64(base + 2u, lanes);
        add64(base + 4u, lines);
        add64(base + 6u, spread);
        add64(base + 8u, octants);
    }
}
