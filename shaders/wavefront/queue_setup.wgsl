// queue_setup: turns queue counters into indirect-dispatch arguments on the GPU, so the host
// never reads a counter back inside the bounce loop (vello's *_setup passes); also resets the
// queues about to be filled and adds queue sizes to the bounce histogram.
// Rust side: src/gpu/wavefront/queue_setup.rs.

#include "wavefront/shared/path_state.wgsl"
#include "wavefront/shared/indirect_args.wgsl"
#include "wavefront/shared/schedule_rule.wgsl"

// Its own group: a buffer bound as storage cannot also feed an indirect dispatch in the same
// pass, so only this pass binds it.
@group(2) @binding(0) var<storage, read_write> indirect: array<u32>;

// Bounces past the last histogram row are added to it (at most 64: COUNTER_SHADE_BASE follows).
override STATS_BOUNCES: u32 = 64u;
override WORKGROUP_SIZE: u32 = 64u;

// (regenerate) Once schedule_decide has put every chunk in the film, the host may still have
// iterations queued (it reads the DONE word back later): they dispatch zero workgroups and
// count nothing, so the report's figures are those of the share's own iterations.
fn share_done() -> bool {
    return REGENERATE && atomicLoad(&counters[COUNTER_DONE]) != 0u;
}

// One indirect dispatch's arguments: workgroups of `group` threads covering `threads`, clamped
// to the adapter's limit (wavefront/shared/indirect_args.wgsl); a clamp is counted for the host to refuse.
fn set_group_args(slot: u32, all_threads: u32, group: u32) {
    let threads = select(all_threads, 0u, share_done());
    if workgroups_needed(threads, group) > MAX_WORKGROUPS {
        atomicAdd(&counters[COUNTER_CLAMPED], 1u);
    }
    indirect[3u * slot] = workgroups_clamped(threads, group);
    indirect[3u * slot + 1u] = 1u;
    indirect[3u * slot + 2u] = 1u;
}

fn set_args(slot: u32, threads: u32) {
    set_group_args(slot, threads, WORKGROUP_SIZE);
}

// Counts `dispatches` recorded indirect dispatches sized to `threads` (empty ones apart): the
// fixed cost the report shows.
fn count_dispatches(threads: u32, dispatches: u32) {
    if share_done() {
        return;
    }
    atomicAdd(&counters[COUNTER_INDIRECT], dispatches);
    if threads == 0u {
        atomicAdd(&counters[COUNTER_EMPTY], dispatches);
    }
}

// The passes over `positions` sized by ARGS_COMPACT: `dispatches` of them recorded (the scan's
// compact_scan and compact_scatter; slot order's sweep; none).
fn set_compact_args(positions: u32, dispatches: u32) {
    atomicStore(&counters[COUNTER_POSITIONS], positions);
    set_group_args(ARGS_COMPACT, positions, SCAN_WG);
    if dispatches > 0u {
        count_dispatches(positions, dispatches);
    }
}

// (regenerate, --refill in-place) The samples the refills in place claimed since the last call
// (intersect's and shade's tickets, path_start.wgsl's `refill_in_place`) become started ones:
// the share's next sample moves past them, up to the ring's fill limit (claims past it failed).
// Called by the single-thread passes that read or move the next sample, the refill's setup and
// the decision pass, before they do: the decision runs last in every batch, so the host's
// read-backs see settled counts.
fn settle_claims() {
    let claims = atomicLoad(&counters[COUNTER_CLAIMS]);
    if claims == 0u {
        return;
    }
    let next = atomicLoad(&counters[COUNTER_NEXT_SAMPLE]);
    let limit = min(atomicLoad(&counters[COUNTER_FILL_LIMIT]), wave_paths());
    atomicStore(&counters[COUNTER_NEXT_SAMPLE], max(next, min(next + claims, limit)));
    atomicStore(&counters[COUNTER_CLAIMS], 0u);
}

// (regenerate) Before the refill: as many of the share's next samples as there are free slots,
// up to the sample ring's end, once at most `wave.refill_live` paths are live (`--refill-below`).
@compute @workgroup_size(1)
fn queue_setup_regenerate() {
    settle_claims();
    let next = atomicLoad(&counters[COUNTER_NEXT_SAMPLE]);
    let free = atomicLoad(&counters[QUEUE_FREE]);
    var n = min(free, atomicLoad(&counters[COUNTER_FILL_LIMIT]) - next);
    if wave.pool - free > wave.refill_live {
        n = 0u; // too many paths still live: the refill waits for a larger batch
    }
    set_args(ARGS_REGENERATE, n);
    count_dispatches(n, 1u);
    atomicStore(&counters[COUNTER_REGEN_BASE], next);
    atomicStore(&counters[COUNTER_NEXT_SAMPLE], next + n);
    // The free queue is a stack: the refill takes its top n entries, and paths ending later push
    // from there again, so slots the ring's end left idle stay free for the next refill. In slot
    // order the pass after shade has just listed the free slots afresh, in ascending order (the
    // scan) or ascending runs (the sweep), and the refill takes the list's first n.
    atomicStore(&counters[COUNTER_FREE_BASE], select(free - n, 0u, slot_order()));
    atomicStore(&counters[QUEUE_FREE], free - n);
    // The refill's entries on the coming iteration's ray queue (filled by the last shade passes,
    // so its count is final here): one reservation instead of an atomic append per new path.
    if COMPACTION != COMPACTION_OFF {
        let q = next_ray_queue();
        let queued = atomicLoad(&counters[q]);
        atomicStore(&counters[COUNTER_REFILL_QUEUED], queued);
        atomicStore(&counters[q], queued + n);
        // --compact-states on: a refill first moves the live states below the live count
        // (compact_states.wgsl), its find pass covering the ray queue and the free list; the
        // lists it builds use the material queues, empty until queue_setup_intersect.
        if COMPACT_STATES {
            atomicStore(&counters[COUNTER_COMPACT_FREE], free);
            atomicStore(&counters[QUEUE_MATERIAL_0], 0u);
            atomicStore(&counters[QUEUE_MATERIAL_0 + 1u], 0u);
            let threads = select(0u, max(queued, free), n > 0u);
            set_args(ARGS_COMPACT_STATES_FIND, threads);
            count_dispatches(threads, 1u);
        }
    }
}

// (regenerate, --compact-states on) Before the move pass: one thread per state to move and per
// free-list entry to rewrite, when this iteration refills.
@compute @workgroup_size(1)
fn queue_setup_compact_states() {
    var threads = 0u;
    if atomicLoad(&counters[COUNTER_NEXT_SAMPLE]) > atomicLoad(&counters[COUNTER_REGEN_BASE]) {
        let movers = atomicLoad(&counters[QUEUE_MATERIAL_0 + 1u]);
        threads = max(movers, atomicLoad(&counters[COUNTER_COMPACT_FREE]));
    }
    set_args(ARGS_COMPACT_STATES_MOVE, threads);
    count_dispatches(threads, 1u);
}

fn record(bounce: u32, q: u32, n: u32) {
    // Past a share's end the queues hold only what no pass will run (the tail's flushed paths),
    // and the counts stay the share's own however far ahead the host recorded.
    if COMPACTION != COMPACTION_OFF && !share_done() {
        let row = min(bounce, STATS_BOUNCES - 1u);
        atomicAdd(&counters[COUNTER_STATS + row * QUEUE_COUNT + q], n);
    }
}

// Before intersect: advance the bounce, size the intersect pass, empty the material queues and
// the next iteration's ray queue (traced in the last iteration; with --refill in-place,
// intersect appends the camera rays of the slots it refills to it).
@compute @workgroup_size(1)
fn queue_setup_intersect() {
    let bounce = atomicAdd(&counters[COUNTER_BOUNCE], 1u) + 1u;
    let q = QUEUE_RAY_0 + bounce % 2u;
    atomicStore(&counters[QUEUE_RAY_0 + (bounce + 1u) % 2u], 0u);
    var n = pool_slots();
    if COMPACTION != COMPACTION_OFF {
        n = atomicLoad(&counters[q]);
    }
    set_args(ARGS_INTERSECT, n);
    count_dispatches(n, 1u);
    if !share_done() {
        atomicAdd(&counters[COUNTER_INTERSECTED], n);
        if n == 0u {
            atomicAdd(&counters[COUNTER_IDLE], 1u);
        }
    }
    record(bounce, QUEUE_RAY_0, n);
    // A scan after intersect (scan method) covers the ray queue's positions.
    set_compact_args(n, select(0u, 2u, COMPACTION == COMPACTION_SCAN));
    for (var k = 0u; k < MATERIAL_KIND_COUNT; k++) {
        atomicStore(&counters[QUEUE_MATERIAL_0 + k], 0u);
    }
    if SHADE_PASSES == SHADE_PER_TEXTURE {
        for (var k = 0u; k < PATTERN_QUEUES; k++) {
            atomicStore(&counters[COUNTER_PATTERN_0 + k], 0u);
        }
    }
}

// Before shade: size each shade pass, empty the shadow queue.
@compute @workgroup_size(1)
fn queue_setup_shade() {
    let bounce = current_bounce();
    var positions = 0u;
    for (var k = 0u; k < MATERIAL_KIND_COUNT; k++) {
        var n = pool_slots();
        if COMPACTION != COMPACTION_OFF {
            n = atomicLoad(&counters[QUEUE_MATERIAL_0 + k]);
        }
        set_args(ARGS_SHADE_0 + k, n);
        if (SHADE_MASK & (1u << k)) != 0u {
            count_dispatches(n, 1u);
        }
        record(bounce, QUEUE_MATERIAL_0 + k, n);
        atomicStore(&counters[COUNTER_SHADE_BASE + k], positions);
        positions += n;
    }
    // --shade sorted: one pass over the material queues end to end.
    if SHADE_PASSES == SHADE_SORTED {
        set_args(ARGS_SHADE_0, positions);
        count_dispatches(positions, 1u);
    }
    // The pattern queues (--shade per-texture, atomic appends only: no scan positions), counted
    // in the histogram with their material kind's queue, lambertian's (the pattern passes shade
    // a textured metal too).
    if SHADE_PASSES == SHADE_PER_TEXTURE {
        for (var k = 0u; k < PATTERN_QUEUES; k++) {
            let n = atomicLoad(&counters[COUNTER_PATTERN_0 + k]);
            set_args(ARGS_PATTERN_0 + k, n);
            if (SHADE_MASK & (1u << (MATERIAL_KIND_COUNT + k))) != 0u {
                count_dispatches(n, 1u);
            }
            record(bounce, QUEUE_MATERIAL_0, n);
        }
    }
    // A scan after shade covers the material queues laid end to end (scan method); in slot
    // order the scan or the sweep (plain slot order with the atomic method: one pass) covers
    // every slot.
    if slot_order() {
        let sweep = COMPACTION == COMPACTION_ATOMIC && !depth_key();
        set_compact_args(pool_slots(), select(2u, 1u, sweep));
    } else {
        set_compact_args(positions, select(0u, 2u, COMPACTION == COMPACTION_SCAN));
    }
    atomicStore(&counters[QUEUE_SHADOW], 0u);
    // In slot order the pass after shade lists the free slots afresh (the sweep appends them).
    if slot_order() {
        atomicStore(&counters[QUEUE_FREE], 0u);
    }
}

// (regenerate) The range of the share's samples accumulate_range adds to the film (twin of
// AccumulateRange in src/layout.rs), written here for the pass after; only schedule_decide binds
// it (group 3).
struct FilmRange {
    first: u32,
    count: u32,
    ring: u32,
    pad: u32,
}
@group(3) @binding(0) var<storage, read_write> film_range: FilmRange;

// accumulate_range's workgroup size (accumulate::WORKGROUP_SIZE).
const ACCUMULATE_WG: u32 = 64u;

fn ring_finished(slot: u32) -> u32 {
    return atomicLoad(&counters[COUNTER_RING_0 + slot]);
}

// (regenerate) After an iteration (every one with --tail megakernel, else every --sync-every):
// the host's check, on the GPU, so the host never reads a counter to go on. At a check (every
// --sync-every iterations; with the tail, every iteration once every sample has started) it
// decides as `schedule::Decision::after` (wavefront/shared/schedule_rule.wgsl): sizes the tail (finishing
// the chunks below the bound) and accumulate_range over the chunks that go into the film, takes
// those chunks out of the ring's counts, moves the refills' limit to the ring's new end, and says
// DONE once every chunk is in the film. Anywhere else both passes get zero workgroups.
@compute @workgroup_size(1)
fn schedule_decide() {
    decide();
}

// (regenerate, --nee on) queue_setup_shadow and schedule_decide in one dispatch, on the iterations
// that have both: the shadow pass after it changes neither the ring's counts nor the ray queue
// the decision reads, and the tail and accumulate_range it sizes are recorded after the shadow
// pass. The shadow pass is sized first: DONE, set last, empties what comes after.
@compute @workgroup_size(1)
fn queue_setup_shadow_decide() {
    setup_shadow();
    decide();
}

fn decide() {
    settle_claims();
    let tail = atomicLoad(&counters[COUNTER_TAIL_ON]) != 0u;
    var tail_threads = 0u;
    var film_threads = 0u;
    var done = share_done();
    if !done {
        let sync_every = atomicLoad(&counters[COUNTER_SYNC_EVERY]);
        // The host records this pass after every iteration with the tail, else after every
        // --sync-every: the iterations each recording stands for.
        let step = select(sync_every, 1u, tail);
        atomicAdd(&counters[COUNTER_ITERATION], step);
        var since = atomicLoad(&counters[COUNTER_SINCE_CHECK]) + step;
        let r = RingShape(wave_paths(), wave.chunk, wave.ring);
        // Whether the first refill starts every sample (a pool of them, up to the ring's end).
        let one_refill = r.paths <= min(wave.pool, ring_fill_limit(r, 0u));
        let refill_done = atomicLoad(&counters[COUNTER_REFILL_DONE]) != 0u;
        if since >= sync_every || (tail && (one_refill || refill_done)) {
            since = 0u;
            let oldest = atomicLoad(&counters[COUNTER_OLDEST]);
            let started = atomicLoad(&counters[COUNTER_NEXT_SAMPLE]);
            var finished = oldest * r.chunk;
            for (var k = 0u; k < r.ring; k++) {
                finished += ring_finished(k);
            }
            let max_live = atomicLoad(&counters[COUNTER_TAIL_MAX_LIVE]);
            let before = atomicLoad(&counters[COUNTER_STARTED_BEFORE]);
            let d = schedule_decision(r, oldest, started, before, finished, max_live, tail);
            atomicStore(&counters[COUNTER_REFILL_DONE], select(1u, 0u, d.refill));
            atomicStore(&counters[COUNTER_STARTED_BEFORE], started);
            if d.tail_bound != 0u {
                atomicStore(&counters[COUNTER_TAIL_BOUND], ring_end(r, d.tail_bound - 1u));
                // Every path on the ray queue the last shade pass filled (the tail skips those
                // of samples from the bound on).
                tail_threads = pool_slots();
                if COMPACTION != COMPACTION_OFF {
                    tail_threads = atomicLoad(&counters[next_ray_queue()]);
                }
                var left = 0u;
                for (var k = d.complete; k < d.tail_bound; k++) {
                    left += ring_len(r, k) - ring_finished(k % r.ring);
                }
                atomicAdd(&counters[COUNTER_TAIL_PASSES], 1u);
                atomicAdd(&counters[COUNTER_TAIL_PATHS], left);
            }
            if d.added > oldest {
                let first = oldest * r.chunk;
                let count = ring_end(r, d.added - 1u) - first;
                film_range = FilmRange(first, count, r.chunk * r.ring, 0u);
                film_threads = min(dispatch.pixel_count, count);
                // Each added chunk ends complete (the tail, next, finishes what it lacks): taking
                // its length off its ring count leaves the zero a refill of the ring's next round
                // starts from, whatever the tail still adds.
                for (var k = oldest; k < d.added; k++) {
                    atomicSub(&counters[COUNTER_RING_0 + k % r.ring], ring_len(r, k));
                }
                atomicStore(&counters[COUNTER_OLDEST], d.added);
                atomicStore(&counters[COUNTER_FILL_LIMIT], ring_fill_limit(r, d.added));
            }
            if d.added == ring_chunks(r) {
                done = true;
            } else if finished == r.paths {
                // Every sample finished, yet chunks are left out: a bug the host reports.
                atomicStore(&counters[COUNTER_FAILED], 1u);
                done = true;
            }
        }
        atomicStore(&counters[COUNTER_SINCE_CHECK], since);
    }
    // Sized and counted before DONE is set, which empties every dispatch after.
    if tail {
        set_args(ARGS_TAIL, tail_threads);
        count_dispatches(tail_threads, 1u);
    }
    set_group_args(ARGS_ACCUMULATE, film_threads, ACCUMULATE_WG);
    count_dispatches(film_threads, 1u);
    if done {
        atomicStore(&counters[COUNTER_DONE], 1u);
    }
}

// Before the shadow pass (--nee on): size it from the shadow rays the shade passes queued.
@compute @workgroup_size(1)
fn queue_setup_shadow() {
    setup_shadow();
}

fn setup_shadow() {
    var n = pool_slots();
    if COMPACTION != COMPACTION_OFF {
        n = atomicLoad(&counters[QUEUE_SHADOW]);
    }
    set_args(ARGS_SHADOW, n);
    count_dispatches(n, 1u);
    record(current_bounce(), QUEUE_SHADOW, n);
}
