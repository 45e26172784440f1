// Queue appends aggregated per subgroup (`--append subgroup`): the active lanes that append to
// the same queue reserve their entries with one atomic, made by the first of them, instead of
// one atomic each on the same counter (the pattern of shaders/megakernel_regenerate_subgroup.wgsl
// and CUDA's warp-aggregated atomics). The loop takes one queue per round, the first active
// lane's: a subgroup whose lanes append to k queues runs k rounds. Correct whatever the driver
// groups together: each group of lanes that runs the subgroup operations together elects its own
// first lane and reserves its own entries.

fn append(q: u32, slot: u32) {
    loop {
        if q == subgroupBroadcastFirst(q) {
            queues[q * wave.pool + take_ticket(queue_counter(q))] = slot;
            break;
        }
    }
}

// Adds one to the statistic in counter word `w`, the same word for every lane: one atomic per
// subgroup.
fn count_one(w: u32) {
    let count = subgroupAdd(1u);
    if subgroupExclusiveAdd(1u) == 0u {
        atomicAdd(&counters[w], count);
    }
}

// The next ticket of counter word `w` (an entry of a queue, or --refill in-place's claim on a
// sample), one atomic per subgroup, made by its first lane: the lanes taking one get consecutive
// tickets.
fn take_ticket(w: u32) -> u32 {
    let rank = subgroupExclusiveAdd(1u);
    let count = subgroupAdd(1u);
    var base = 0u;
    if rank == 0u {
        base = atomicAdd(&counters[w], count);
    }
    return subgroupBroadcastFirst(base) + rank;
}
