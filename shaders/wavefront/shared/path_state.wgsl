// The wavefront's path pool (structure of arrays) and queues: bind group 1 of every wavefront
// pass. Rust side: src/gpu/wavefront/path_state.rs. `dispatch` is a share of the image's samples
// (pixel_count × sample_count); its sample l is sample (start + l / pixel_count) of pixel
// (offset + l % pixel_count). With `--schedule waves` the share is one wave and slot l traces
// sample l, so neither is stored. With `--schedule regenerate` the share is far larger than the
// pool: each slot stores the sample it traces and its bounce, and a slot whose path ended takes
// the share's next sample (generate.wgsl's `regenerate`), so the pool stays full. Finished
// samples wait in a ring of `wave.ring` chunks of `wave.chunk` samples for the accumulate pass,
// which runs as the oldest chunks complete; refills stop at the ring's end (COUNTER_FILL_LIMIT,
// advanced on the GPU by schedule_decide), so the pool drains once per share, not per chunk.

#include "shared/dispatch.wgsl"
#include "shared/kinds.wgsl"

// Pipeline constant: true with `--schedule regenerate`.
override REGENERATE: bool = false;
// Pipeline constant (regenerate): a slot whose path ends in intersect or shade takes the share's
// next sample there and then, its camera ray queued for the next iteration (`--refill in-place`,
// path_start.wgsl); the refill pass takes only the slots freed while the sample ring was full.
// A constant, not a uniform, so that without it none of that code is compiled in.
override REFILL_IN_PLACE: bool = false;

// The queue, counter and argument layout follows MATERIAL_KIND_COUNT (shared/kinds.wgsl): a kind
// adds a material queue, a shade pass's first scan position and an argument slot, and every slot
// after them is computed from those. Twin of QueueLayout in src/gpu/wavefront/path_state.rs.
// Queue ids: regions of `queues`, each `pool` entries long, and their counters.
const QUEUE_RAY_0: u32 = 0u;        // ray queues alternate by iteration parity
const QUEUE_MATERIAL_0: u32 = 2u;   // + material kind (one shared queue with --shade single)
const QUEUE_SHADOW: u32 = QUEUE_MATERIAL_0 + MATERIAL_KIND_COUNT; // shadow rays (--nee on); always appended atomically
const QUEUE_FREE: u32 = QUEUE_SHADOW + 1u; // (regenerate) slots whose path ended; always atomic
const QUEUE_COUNT: u32 = QUEUE_FREE + 1u;
// (--shade per-texture) + texture kind − TEXTURE_NOISE: a queue per costly pattern, regions after
// the QUEUE_COUNT others, their counts at COUNTER_PATTERN_0.
const QUEUE_PATTERN_0: u32 = QUEUE_COUNT;
const PATTERN_QUEUES: u32 = 8u;
// Word indices in `counters` besides the queue counts.
const COUNTER_BOUNCE: u32 = QUEUE_COUNT;     // current iteration (= bounce in waves), advanced by queue_setup_intersect
const COUNTER_POSITIONS: u32 = QUEUE_COUNT + 1u;  // queue positions the next scan compaction covers
const COUNTER_STATS: u32 = QUEUE_COUNT + 2u;     // + bounce * QUEUE_COUNT + queue: paths queued, summed over waves
const COUNTER_SHADE_BASE: u32 = COUNTER_STATS + 64u * QUEUE_COUNT; // + kind: first scan position of each shade pass
// Scheduling counters, read back by the host after each batch (src/gpu/wavefront/schedule.rs);
// offsets from COUNTER_SCHEDULE are schedule_word's in path_state.rs.
const COUNTER_SCHEDULE: u32 = COUNTER_SHADE_BASE + MATERIAL_KIND_COUNT;
const COUNTER_NEXT_SAMPLE: u32 = COUNTER_SCHEDULE + 0u;  // (regenerate) the share's next sample to start
// (regenerate) first ray-queue entry of this iteration's refill: queue_setup_regenerate reserves
// the refill's entries, so `regenerate` appends without an atomic.
const COUNTER_REFILL_QUEUED: u32 = COUNTER_SCHEDULE + 1u;
const COUNTER_REGEN_BASE: u32 = COUNTER_SCHEDULE + 2u;   // (regenerate) first sample of this iteration's refill
const COUNTER_EMPTY: u32 = COUNTER_SCHEDULE + 3u;        // indirect dispatches sized to zero workgroups
const COUNTER_INDIRECT: u32 = COUNTER_SCHEDULE + 4u;     // indirect dispatches sized
const COUNTER_INTERSECTED: u32 = COUNTER_SCHEDULE + 5u;  // paths queued for intersect, summed
const COUNTER_IDLE: u32 = COUNTER_SCHEDULE + 6u;        // iterations that found no ray to trace
// (regenerate) Written by schedule_decide (queue_setup.wgsl):
const COUNTER_FILL_LIMIT: u32 = COUNTER_SCHEDULE + 7u;  // refills start samples below this (the ring's end)
const COUNTER_TAIL_BOUND: u32 = COUNTER_SCHEDULE + 8u;  // the tail finishes the paths of samples below this
const COUNTER_FREE_BASE: u32 = COUNTER_SCHEDULE + 9u;   // (regenerate) first free-queue entry of this refill
const COUNTER_CLAMPED: u32 = COUNTER_SCHEDULE + 10u;     // indirect arguments clamped to the adapter's limit (a bug if > 0)
// (regenerate, --compact-states on) States moved and compactions run, summed over a share; the
// free slots at the refill; compactions whose free list and ray queue disagreed (a bug if > 0).
const COUNTER_STATES_MOVED: u32 = COUNTER_SCHEDULE + 11u;
const COUNTER_COMPACTIONS: u32 = COUNTER_SCHEDULE + 12u;
const COUNTER_COMPACT_FREE: u32 = COUNTER_SCHEDULE + 13u;
const COUNTER_COMPACT_MISMATCH: u32 = COUNTER_SCHEDULE + 14u;
// (regenerate) The decision pass's words (schedule_word in path_state.rs; queue_setup.wgsl's
// schedule_decide): the first chunk not in the film, the samples started at the last check, the
// share done, its iterations, iterations since the last check, the last check found every sample
// started, tail passes and paths; written by the host at the share's start: --sync-every, the
// tail on, the most live paths it runs at; every sample finished with chunks left out (a bug).
const COUNTER_OLDEST: u32 = COUNTER_SCHEDULE + 15u;
const COUNTER_STARTED_BEFORE: u32 = COUNTER_SCHEDULE + 16u;
const COUNTER_DONE: u32 = COUNTER_SCHEDULE + 17u;
const COUNTER_ITERATION: u32 = COUNTER_SCHEDULE + 18u;
const COUNTER_SINCE_CHECK: u32 = COUNTER_SCHEDULE + 19u;
const COUNTER_REFILL_DONE: u32 = COUNTER_SCHEDULE + 20u;
const COUNTER_TAIL_PASSES: u32 = COUNTER_SCHEDULE + 21u;
const COUNTER_TAIL_PATHS: u32 = COUNTER_SCHEDULE + 22u;
const COUNTER_SYNC_EVERY: u32 = COUNTER_SCHEDULE + 23u;
const COUNTER_TAIL_ON: u32 = COUNTER_SCHEDULE + 24u;
const COUNTER_TAIL_MAX_LIVE: u32 = COUNTER_SCHEDULE + 25u;
const COUNTER_FAILED: u32 = COUNTER_SCHEDULE + 26u;
// (regenerate, --refill in-place) Samples claimed by slots refilled where their paths ended
// since the claims were last settled (`settle_claims`): the next samples are the share's next
// sample + the claim's ticket. Then the slots refilled so, by intersect and by shade.
const COUNTER_CLAIMS: u32 = COUNTER_SCHEDULE + 27u;
const COUNTER_REFILLED_INTERSECT: u32 = COUNTER_SCHEDULE + 28u;
const COUNTER_REFILLED_SHADE: u32 = COUNTER_SCHEDULE + 29u;
const COUNTER_RING_0: u32 = COUNTER_SCHEDULE + 30u;      // + ring chunk: its samples finished
// (--shade per-texture) + pattern: the pattern queues' counts, after the ring's 1024 chunks.
const COUNTER_PATTERN_0: u32 = COUNTER_RING_0 + 1024u;
// (regenerate, CAMERA_IN_PLACE) Camera rays that hit, and paths going on from that hit: in
// the histogram's second row, which regenerating renders (one row) leave unused. In waves the
// histogram has them per bounce. The bounce-0 counts of the path-state traffic model
// (src/gpu/wavefront/traffic.rs).
const COUNTER_CAMERA_HITS: u32 = COUNTER_STATS + QUEUE_COUNT;
const COUNTER_FIRST_CONTINUING: u32 = COUNTER_STATS + QUEUE_COUNT + 1u;
// Indirect-dispatch argument slots (3 words each) in queue_setup's `indirect`.
const ARGS_INTERSECT: u32 = 0u;
const ARGS_SHADE_0: u32 = 1u;       // + material kind
const ARGS_COMPACT: u32 = ARGS_SHADE_0 + MATERIAL_KIND_COUNT; // the scan passes over the positions just produced
const ARGS_SHADOW: u32 = ARGS_COMPACT + 1u;
const ARGS_REGENERATE: u32 = ARGS_COMPACT + 2u;
const ARGS_TAIL: u32 = ARGS_COMPACT + 3u;
const ARGS_COMPACT_STATES_FIND: u32 = ARGS_COMPACT + 4u;  // (--compact-states on) the find pass, then the move pass
const ARGS_COMPACT_STATES_MOVE: u32 = ARGS_COMPACT + 5u;
const ARGS_ACCUMULATE: u32 = ARGS_COMPACT + 6u;  // (regenerate) accumulate_range, sized by schedule_decide
const ARGS_PATTERN_0: u32 = ARGS_COMPACT + 7u;   // (--shade per-texture) + pattern: its shade pass
// Workgroup size of the passes ARGS_COMPACT sizes: the scan (wavefront/compact.wgsl) and slot
// order's sweep (wavefront/slot_sweep.wgsl). SCAN_WG in path_state.rs.
const SCAN_WG: u32 = 256u;

// The word of `counters` counting queue `q`'s entries.
fn queue_counter(q: u32) -> u32 {
    return select(q, COUNTER_PATTERN_0 + q - QUEUE_PATTERN_0, q >= QUEUE_PATTERN_0);
}

// A path that no pass should touch again.
const DEAD: u32 = 0xffffffffu;
// (regenerate, CAMERA_IN_PLACE) The mark of a refill's ray-queue entries: the slot traces its
// camera ray, which intersect makes (a slot's bounce is not known there without reading it). Slots
// stay below 2^31: the pool is bounded by one binding of 4-byte queue entries per slot and queue.
const CAMERA_RAY: u32 = 0x80000000u;
// (regenerate) A path the tail finished while its slot was still on the ray queue: the next
// intersect frees the slot (a slot must leave every queue before a refill takes it).
const FLUSHED: u32 = 0xfffffffdu;

// The knobs as pipeline constants: the pass graph gives every pass over the path state the same
// values (src/gpu/wavefront/plan.rs, `Plan::knob_constants`), so a pass is compiled with only
// the code its knobs run.
// How queues are built (`--compaction`, `--compaction-method`): none (every pass covers the
// whole pool), atomic appends, or the prefix-sum scan.
override COMPACTION: u32 = 1u;
const COMPACTION_OFF: u32 = 0u;
const COMPACTION_ATOMIC: u32 = 1u;
const COMPACTION_SCAN: u32 = 2u;
// How hits are shaded (`--shade`): a pass per material kind; and one per costly pattern
// (`per-texture`); one pass with a switch (`single`); one pass over the material queues end to
// end (`sorted`).
override SHADE_PASSES: u32 = 0u;
const SHADE_PER_MATERIAL: u32 = 0u;
const SHADE_PER_TEXTURE: u32 = 1u;
const SHADE_SINGLE: u32 = 2u;
const SHADE_SORTED: u32 = 3u;
// Bit k: the shade pass of queue QUEUE_MATERIAL_0 + k is recorded; bit MATERIAL_KIND_COUNT + p:
// the pattern p's (to count the empty ones).
override SHADE_MASK: u32 = 0u;
// The order of the paths in each queue (`--queue-order`): as they arrive; slot order (the ray
// queue, free list and shadow queue built by a pass over the pool's slots: the scan, or the
// atomic method's sweep); slot order keyed by depth (`slot-depth`: the paths on their first
// bounce after the others).
override QUEUE_ORDER: u32 = 0u;
const ORDER_ARRIVAL: u32 = 0u;
const ORDER_SLOT: u32 = 1u;
const ORDER_SLOT_DEPTH: u32 = 2u;
// (regenerate) Compact the live states below the live count before each refill
// (`--compact-states on`).
override COMPACT_STATES: bool = false;
// Camera rays are not stored (queues on, no ray sort): intersect and shade make a camera ray
// from its slot's pixel and sample (wavefront/shared/path_camera.wgsl), and generate writes
// only the queue entry (and, regenerating, the slot's sample).
override CAMERA_IN_PLACE: bool = false;
// The passes that consume a queue (intersect, shade, shadow, the refill) are launched at the
// pool's size, not sized by a setup pass (`--launch pool`): threads past the queue's length
// return (queued_entry), and past a regenerating share's end every thread does.
override LAUNCH_POOL: bool = false;

// The job's numbers, constant over a render; twin of WaveUniform in src/layout.rs.
struct Wave {
    // Queue region length (the pool size).
    pool: u32,
    // (regenerate) Samples per chunk of the sample ring, and chunks in the ring.
    chunk: u32,
    ring: u32,
    // (regenerate) A refill runs only when at most this many paths are live (`--refill-below` ×
    // pool; the pool itself: every iteration).
    refill_live: u32,
}

@group(1) @binding(0) var<uniform> dispatch: Dispatch;
@group(1) @binding(1) var<uniform> wave: Wave;
// xyz: ray origin; w: distance of the hit found by intersect.
@group(1) @binding(2) var<storage, read_write> path_origin: array<vec4<f32>>;
// xyz: ray direction; w: bitcast primitive slot hit, or DEAD once the path has ended.
@group(1) @binding(3) var<storage, read_write> path_dir: array<vec4<f32>>;
// xyz: throughput; w: when the last hit sampled the lights, the diffuse bounce's density for the
// ray now traced (MIS weight of the emission it finds), else 0.
@group(1) @binding(4) var<storage, read_write> path_throughput: array<vec4<f32>>;
// rgb: the path's radiance so far; w: shadow rays traced, and once the path has ended every ray it
// traced (finish_path; both read by the accumulate pass).
@group(1) @binding(5) var<storage, read_write> radiance: array<vec4<f32>>;
@group(1) @binding(6) var<storage, read_write> queues: array<u32>;
@group(1) @binding(7) var<storage, read_write> counters: array<atomic<u32>>;
// Scan compaction, indexed by the producing pass's queue position (so a scan covers only the
// paths just processed) or, in slot order, by slot: the queue each goes to next (or DEAD), its
// slot, and offsets. In slot order (either compaction method) every slot's entry says, when the
// pass after shade (scan or sweep) runs, where its path goes next (DEAD for a slot holding no
// path), with SHADOW_PENDING set when it also has a shadow ray queued.
@group(1) @binding(8) var<storage, read_write> next_queue: array<u32>;
@group(1) @binding(9) var<storage, read_write> scan_offset: array<u32>;
@group(1) @binding(10) var<storage, read_write> block_sums: array<vec4<u32>>;
@group(1) @binding(11) var<storage, read_write> scan_slot: array<u32>;
// The pending shadow ray (--nee on), from path_origin.xyz: xyz direction, w its t_max.
@group(1) @binding(12) var<storage, read_write> shadow_ray: array<vec4<f32>>;
// rgb: what it adds to the radiance if unblocked; w: the bits of its light's slot + 1 while it
// is pending (which the shadow ray skips), 0 otherwise.
@group(1) @binding(13) var<storage, read_write> shadow_weight: array<vec4<f32>>;
// (regenerate) x: the sample the slot traces (index l in the share); y: its bounce.
@group(1) @binding(14) var<storage, read_write> path_sample: array<vec2<u32>>;
// (regenerate) each finished sample's radiance, at l modulo the ring's samples: the accumulate
// pass's input, so the film adds samples in the same order as with waves.
@group(1) @binding(15) var<storage, read_write> samples: array<vec4<f32>>;

// Samples in this share of the image (a wave; when regenerating, usually the whole image).
fn wave_paths() -> u32 {
    return dispatch.pixel_count * dispatch.sample_count;
}

// Slots a pass over the whole pool covers (no compaction): the wave's paths, or the whole pool.
fn pool_slots() -> u32 {
    if REGENERATE {
        return wave.pool;
    }
    return wave_paths();
}

// The sample `slot` traces (its index l in this share).
fn slot_index(slot: u32) -> u32 {
    if REGENERATE {
        return path_sample[slot].x;
    }
    return slot;
}

fn sample_pixel(l: u32) -> u32 {
    return dispatch.pixel_offset + l % dispatch.pixel_count;
}

fn sample_number(l: u32) -> u32 {
    return dispatch.sample_start + l / dispatch.pixel_count;
}

fn slot_pixel(slot: u32) -> u32 {
    return sample_pixel(slot_index(slot));
}

fn slot_sample(slot: u32) -> u32 {
    return sample_number(slot_index(slot));
}

// The iteration: waves advance every path one bounce per iteration; when regenerating, paths in
// the pool are at different bounces, and only the queues' parity follows the iteration.
fn current_bounce() -> u32 {
    return atomicLoad(&counters[COUNTER_BOUNCE]);
}

// The ray queue this iteration's shade passes fill and the next iteration traces (the refill
// appends to it, the tail takes it).
fn next_ray_queue() -> u32 {
    return QUEUE_RAY_0 + (current_bounce() + 1u) % 2u;
}

// The bounce of the path in `slot`.
fn path_bounce(slot: u32) -> u32 {
    if REGENERATE {
        return path_sample[slot].y;
    }
    return current_bounce();
}

// A camera ray's path has gathered nothing and its throughput is one: generate writes neither, so
// a path's radiance and throughput are read from memory only after its first bounce (shade writes
// both for a path that goes on from bounce 0, and a shadow ray's light is added after that).
fn path_radiance(slot: u32, bounce: u32) -> vec4<f32> {
    if bounce == 0u {
        return vec4<f32>(0.0);
    }
    return radiance[slot];
}

// xyz: the throughput; w: the MIS density of the ray now traced (0: none), as `path_throughput`.
fn path_throughput_at(slot: u32, bounce: u32) -> vec4<f32> {
    if bounce == 0u {
        return vec4<f32>(1.0, 1.0, 1.0, 0.0);
    }
    return path_throughput[slot];
}

// (regenerate) A finished path's `value` into the sample ring, counted for its chunk.
fn store_sample(slot: u32, value: vec4<f32>) {
    let l = path_sample[slot].x;
    samples[l % (wave.chunk * wave.ring)] = value;
    atomicAdd(&counters[COUNTER_RING_0 + (l / wave.chunk) % wave.ring], 1u);
}

// `append(q, slot)`: one atomic per lane here; the `.subgroup` variant (build.rs) swaps in
// wavefront/shared/append_subgroup.wgsl, one atomic per subgroup and queue (`--append`).
#include "wavefront/shared/append.wgsl"

// Whether queues are kept in slot order (`--queue-order slot`): a pass after shade (the stable
// scan, or the atomic method's sweep: runs of ascending slots) runs over the pool's slots, so
// the ray queue lists its paths by slot and a subgroup's lanes read neighbouring path states
// whatever order the paths arrived in; the free list (regenerate) and the shadow queue come out
// of the same pass. The material queues keep the ray queue's order
// (the stable scan) or its subgroups' runs (atomic appends).
fn slot_order() -> bool {
    return QUEUE_ORDER != ORDER_ARRIVAL;
}

// Whether the scan after shade keys the ray queue by depth (`--queue-order slot-depth`): the
// paths about to trace their first bounce after the camera ray (the children of the last
// refill, in ascending slots: consecutive samples) form one run after the others, as they do
// in a wave, rather than being interleaved by slot with paths at every depth.
fn depth_key() -> bool {
    return QUEUE_ORDER == ORDER_SLOT_DEPTH;
}

// In slot order, next_queue's flags for a path that also has a shadow ray queued, for one
// whose next ray is its first bounce (depth key), and (--refill in-place, camera rays made in
// place) for a slot just refilled, whose ray-queue entry the pass after shade marks CAMERA_RAY.
const SHADOW_PENDING: u32 = 0x100u;
const FIRST_BOUNCE: u32 = 0x200u;
const NEW_CAMERA: u32 = 0x400u;

// (regenerate) `slot` is on no queue and traces nothing: the next refill may take it. In slot
// order the pass after shade lists every free slot itself.
fn free_slot(slot: u32) {
    if !slot_order() {
        append(QUEUE_FREE, slot);
    }
}

// Where the scan compaction keeps what it knows of `slot`, processed at queue position
// `position`: the position (arrival order) or the slot itself (slot order).
fn scan_index(slot: u32, position: u32) -> u32 {
    return select(position, slot, slot_order());
}

// Puts `slot`, processed at scan position `position`, on the next iteration's ray queue, and
// says whether it has a shadow ray queued too (`enqueue_shadow` queued it) and whether the ray is
// the path's first bounce after the camera ray.
fn enqueue_ray(slot: u32, position: u32, shadow: bool, first_bounce: bool) {
    let q = next_ray_queue();
    if slot_order() {
        next_queue[slot] = q | select(0u, SHADOW_PENDING, shadow) | select(0u, FIRST_BOUNCE, first_bounce);
    } else {
        enqueue(q, slot, position);
    }
}

// Puts `slot`, processed at scan position `position`, on queue `q`: appended atomically, or
// marked for the scan, per the compaction knob.
fn enqueue(q: u32, slot: u32, position: u32) {
    if COMPACTION == COMPACTION_ATOMIC {
        append(q, slot);
    } else if COMPACTION == COMPACTION_SCAN {
        let p = scan_index(slot, position);
        next_queue[p] = q;
        if !slot_order() {
            scan_slot[p] = slot;
        }
    }
}

// Puts `slot`'s shadow ray on the shadow queue: appended atomically with either compaction
// method in arrival order (a path can go to both the next ray queue and this one, which a scan's
// single target per position cannot express); in slot order `enqueue_ray` flags it for the pass
// after shade;
// without compaction the pending shadow weight alone marks it.
fn enqueue_shadow(slot: u32) {
    if COMPACTION != COMPACTION_OFF && !slot_order() {
        append(QUEUE_SHADOW, slot);
    }
}

// The path in `slot`, processed at scan position `position`, has ended: the scan skips it.
fn retire(slot: u32, position: u32) {
    if slot_order() {
        next_queue[slot] = DEAD;
    } else if COMPACTION == COMPACTION_SCAN {
        next_queue[position] = DEAD;
    }
}

// The path slot handled by thread `i` of a pass over queue `q`, or DEAD past the queue's end.
// Without compaction, thread i handles slot i of the whole pool.
// (--launch pool, regenerate) Whether the share is done (schedule_decide set DONE): in the
// iterations the host recorded past its end, which indirect launches give zero workgroups, every
// thread of a pool-size launch runs, so intersect and shade return when this says so. (The
// refill starts nothing once every sample has; the shadow pass finds its queue emptied by
// queue_setup_shade and filled by no shade pass; the tail and accumulate_range, sized by the
// decision that sets DONE, keep their indirect launches.)
fn launched_past_done() -> bool {
    return REGENERATE && LAUNCH_POOL && atomicLoad(&counters[COUNTER_DONE]) != 0u;
}

fn queued_slot(q: u32, i: u32) -> u32 {
    let entry = queued_entry(q, i);
    if entry == DEAD {
        return DEAD;
    }
    return entry & ~CAMERA_RAY;
}

// The entry at position `i` of the ray queue this iteration traces, CAMERA_RAY mark and all: a
// wave's camera rays made in place have no entries, their slots in order (generate writes none).
fn ray_queue_entry(i: u32) -> u32 {
    let q = QUEUE_RAY_0 + current_bounce() % 2u;
    if !REGENERATE && CAMERA_IN_PLACE && current_bounce() == 0u {
        return select(DEAD, i, i < atomicLoad(&counters[q]));
    }
    return queued_entry(q, i);
}

// `queued_slot` with its CAMERA_RAY mark, if any.
fn queued_entry(q: u32, i: u32) -> u32 {
    if COMPACTION == COMPACTION_OFF {
        return select(DEAD, i, i < pool_slots());
    }
    if i >= atomicLoad(&counters[queue_counter(q)]) {
        return DEAD;
    }
    return queues[q * wave.pool + i];
}
