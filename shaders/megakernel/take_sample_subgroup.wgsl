// The regenerating megakernel's sample fetch with subgroups (Aila & Laine 2009): the lanes that
// need a sample take consecutive ones with one atomic per subgroup, broadcast to them, so
// neighbouring lanes start neighbouring pixels. Swapped in for take_sample.wgsl on adapters with
// subgroups (src/gpu/shader_variants.rs).

// Called by every lane of the subgroup at once (the loop keeps them together, see
// megakernel_regenerate.wgsl): the subgroup operations see the whole subgroup, and the one
// atomic's branch reconverges at its end, where its header was uniform.
fn take_sample(wants: bool) -> u32 {
    let asks = select(0u, 1u, wants);
    let count = subgroupAdd(asks);
    let rank = subgroupExclusiveAdd(asks);
    var base = 0u;
    // The first active lane (no active lane before it) asks for the whole subgroup.
    if subgroupExclusiveAdd(1u) == 0u && count > 0u {
        base = atomicAdd(&work[WORK_NEXT], count);
    }
    base = subgroupBroadcastFirst(base);
    if !wants {
        return NO_SAMPLE;
    }
    return base + rank;
}

// The loop ends for the whole subgroup at once, so `take_sample` stays in uniform control flow.
fn leave_together(done: bool) -> bool {
    return subgroupAll(done);
}
