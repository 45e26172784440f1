// Queue appends, one atomic per lane (`--append lane`, and adapters without subgroups): appends
// `slot` to queue `q` (`counters[q]` counts its entries). The order within a queue is whatever
// order the atomics run in; nothing depends on it (the film adds samples in sample order).

fn append(q: u32, slot: u32) {
    queues[q * wave.pool + take_ticket(queue_counter(q))] = slot;
}

// Adds one to the statistic in counter word `w`, the same word for every lane.
fn count_one(w: u32) {
    atomicAdd(&counters[w], 1u);
}

// The next ticket of counter word `w` (an entry of a queue, or --refill in-place's claim on a
// sample): 0, 1, 2, … in whatever order the lanes take them.
fn take_ticket(w: u32) -> u32 {
    return atomicAdd(&counters[w], 1u);
}
