// The regenerating schedule's rule after a check, on the GPU: the WGSL twin of
// `schedule::Decision::after` and `schedule::Ring` (src/gpu/wavefront/schedule.rs), which stay the
// documented rule and the CPU replay's. tests/suite/schedule_rule.rs runs both over randomized
// ring states (shaders/tests/schedule_probe.wgsl) and requires the same decisions.
// The includer defines `fn ring_finished(slot: u32) -> u32`: the finished samples of the chunk
// at that index of the ring. Where Rust compares a path count with the threshold × pool as an
// f64, this takes `max_live` = floor(threshold × pool): for a whole count n, n <= x exactly when
// n <= floor(x).

// A share of `paths` samples in chunks of `chunk`, `ring` of them held at once (`schedule::Ring`).
struct RingShape {
    paths: u32,
    chunk: u32,
    ring: u32,
}

fn ring_chunks(r: RingShape) -> u32 {
    return max(r.paths / r.chunk + select(0u, 1u, r.paths % r.chunk != 0u), 1u);
}

// One past chunk c's last sample (c below ring_chunks: paths and chunk are below 2^31, so the
// product stays within u32).
fn ring_end(r: RingShape, c: u32) -> u32 {
    return min((c + 1u) * r.chunk, r.paths);
}

fn ring_len(r: RingShape, c: u32) -> u32 {
    return ring_end(r, c) - c * r.chunk;
}

fn ring_fill_limit(r: RingShape, oldest: u32) -> u32 {
    if oldest + r.ring >= ring_chunks(r) {
        return r.paths;
    }
    return (oldest + r.ring) * r.chunk;
}

fn ring_complete_from(r: RingShape, oldest: u32) -> u32 {
    var c = oldest;
    let window = min(ring_chunks(r), oldest + r.ring);
    while c < window && ring_finished(c % r.ring) == ring_len(r, c) {
        c += 1u;
    }
    return c;
}

fn ring_flush_to(r: RingShape, complete: u32, started: u32, expected: u32, max_live: u32) -> u32 {
    var c = complete;
    loop {
        if c >= ring_chunks(r) || ring_fill_limit(r, c) >= r.paths {
            break;
        }
        let limit = ring_fill_limit(r, c);
        let room = select(0u, limit - started, limit > started);
        if room >= expected || ring_end(r, c) > started || ring_len(r, c) - ring_finished(c % r.ring) > max_live {
            break;
        }
        c += 1u;
    }
    return c;
}

// `schedule::Decision`; tail_bound 0 for None (a bound is above `complete`, so never 0).
struct Decided {
    refill: bool,
    complete: u32,
    tail_bound: u32,
    added: u32,
}

// `Decision::after` for the counters `started` and `finished` (the chunks before `oldest` and
// the ring's counts), the samples started at the last check, and with the tail where `tail`.
fn schedule_decision(r: RingShape, oldest: u32, started: u32, started_before: u32, finished: u32,
                     max_live: u32, tail: bool) -> Decided {
    let complete = ring_complete_from(r, oldest);
    var tail_bound = 0u;
    if tail {
        var bound = 0u;
        if started == r.paths && started - finished <= max_live {
            bound = ring_chunks(r);
        } else {
            bound = ring_flush_to(r, complete, started, started - started_before, max_live);
        }
        if bound > complete {
            tail_bound = bound;
        }
    }
    return Decided(started < r.paths, complete, tail_bound, select(complete, tail_bound, tail_bound != 0u));
}
