// Test kernel: the regenerating schedule's rule as the GPU runs it (wavefront/shared/schedule_rule.wgsl),
// one thread per ring state the host chooses, so tests/suite/schedule_rule.rs can compare each
// decision with `schedule::Decision::after`.

#include "wavefront/shared/schedule_rule.wgsl"

// Per case CASE_WORDS words: paths, chunk, ring, oldest, started, started_before, finished,
// max_live, tail, then the ring's counts (at most CASE_WORDS - 9 chunks).
@group(0) @binding(0) var<storage, read> cases: array<u32>;
// Per case: refill, complete, tail_bound (0: none), added.
@group(0) @binding(1) var<storage, read_write> decided: array<u32>;

const CASE_WORDS: u32 = 32u;

var<private> case_base: u32;

fn ring_finished(slot: u32) -> u32 {
    return cases[case_base + 9u + slot];
}

@compute @workgroup_size(64)
fn schedule_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&cases) / CASE_WORDS {
        return;
    }
    case_base = i * CASE_WORDS;
    let w = case_base;
    let r = RingShape(cases[w], cases[w + 1u], cases[w + 2u]);
    let d = schedule_decision(r, cases[w + 3u], cases[w + 4u], cases[w + 5u], cases[w + 6u], cases[w + 7u],
                              cases[w + 8u] != 0u);
    decided[4u * i] = select(0u, 1u, d.refill);
    decided[4u * i + 1u] = d.complete;
    decided[4u * i + 2u] = d.tail_bound;
    decided[4u * i + 3u] = d.added;
}
