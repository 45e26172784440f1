//! Queue order (issue 26, `--queue-order`): slot order changes which lanes run together, never
//! what a sample computes, so every combination gives the waves' film bit for bit; it is refused
//! where there are no queues to order; and it does what it is for, measured by the coherence
//! counters.

use crate::common;
use crate::common::render_wavefront as run;

use wavetrace::gpu::instrument::Coherence;
use wavetrace::gpu::wavefront::{Compaction, QueueOrder, Schedule, Tail, WavefrontOptions};
use wavetrace::options::PoolSize;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(spp: u32, nee: bool) -> RenderSettings {
    RenderSettings {
        width: 40,
        height: 24,
        spp,
        max_depth: 12,
        seed: 5,
        accel: Accel::Bvh,
        nee,
        roulette: false,
    }
}

/// Slot order, keyed by depth or not, with both compaction methods, waves and regeneration, with
/// and without the tail and NEE (the shadow queue then comes out of the scan or the sweep too),
/// with a pool small enough for many refills and a ring of two chunks (refills stop at its end):
/// the same film as waves in arrival order, bit for bit (with the tail: the same paths, radiance
/// up to rounding, `common::assert_same_paths`). Each (case, order) pair on one of the scenes.
#[test]
fn slot_order_gives_the_waves_film() {
    let Some(_) = common::gpu() else { return };
    for (i, (scene, nee)) in [("cornell", true), ("rtiow-final", false)].into_iter().enumerate() {
        let s = settings(8, nee);
        let base = WavefrontOptions { pool_size: Some(PoolSize::Paths(1500)), ..Default::default() };
        let waves = run(scene, &s, base, false).unwrap().film;
        assert!(waves.image_mean() > 0.0, "{scene}: a black film proves nothing");
        let cases = [
            (Compaction::Scan, Schedule::Waves, Tail::Off, 8),
            (Compaction::Scan, Schedule::Regenerate, Tail::Off, 8),
            (Compaction::Scan, Schedule::Regenerate, Tail::Megakernel, 8),
            (Compaction::Scan, Schedule::Regenerate, Tail::Off, 2),
            (Compaction::Atomic, Schedule::Waves, Tail::Off, 8),
            (Compaction::Atomic, Schedule::Regenerate, Tail::Off, 2),
            (Compaction::Atomic, Schedule::Regenerate, Tail::Megakernel, 8),
        ];
        // Each scene takes every other case and order in turn, so every pair meets a scene and
        // both orders meet NEE's shadow queue (each run compiles its own pipelines: half the
        // test's cost with a cold shader cache).
        let pairs = cases.into_iter().flat_map(|c| [(c, QueueOrder::Slot), (c, QueueOrder::SlotDepth)]);
        let mine = pairs.enumerate().filter(|(k, _)| (k / 2 + k % 2 + i) % 2 == 0).map(|(_, p)| p);
        for ((compaction, schedule, tail, chunk_pools), order) in mine {
            let wf = WavefrontOptions { compaction, schedule, tail, chunk_pools, queue_order: order, ..base };
            let out = run(scene, &s, wf, false).unwrap();
            let what = format!(
                "{scene} nee={nee} {order:?} {compaction:?} {schedule:?} {tail:?} chunk_pools={chunk_pools}"
            );
            common::assert_waves_film(&what, &out.film, &waves, tail);
            // Plain slot order with atomic appends builds its queues by the sweep; the scan
            // method and the depth key by the scan over the pool.
            let passes = &out.timings.as_ref().unwrap().passes;
            let sweep = order == QueueOrder::Slot && compaction == Compaction::Atomic;
            assert_eq!(passes.contains_key("slot_sweep"), sweep, "{what}: {:?}", passes.keys());
            assert_eq!(passes.contains_key("compact_scan"), !sweep, "{what}: {:?}", passes.keys());
            if schedule == Schedule::Regenerate {
                let st = out.schedule.unwrap();
                assert!(st.iterations > 12, "{what}: the pool was refilled ({} iterations)", st.iterations);
            }
        }
    }
}

/// Slot order orders queues: without compaction (no queues) it is refused, naming the knob and
/// what it needs, before anything runs.
#[test]
fn slot_order_needs_queues() {
    let Some(_) = common::gpu() else { return };
    for (order, name) in
        [(QueueOrder::Slot, "--queue-order slot "), (QueueOrder::SlotDepth, "--queue-order slot-depth ")]
    {
        let wf = WavefrontOptions { compaction: Compaction::Off, queue_order: order, ..Default::default() };
        let err = run("three-spheres", &settings(1, false), wf, false).unwrap_err().to_string();
        assert!(err.contains(name) && err.contains("--compaction on"), "{err}");
    }
}

/// The mean of a coherence counter per intersect subgroup over the iterations after the first
/// eight (the refills' steady state), weighted by subgroups; enough subgroups to mean something.
fn steady_mean(c: &[Coherence], counter: impl Fn(&Coherence) -> f64, what: &str) -> f64 {
    let steady: Vec<_> = c.iter().filter(|b| b.first_iteration >= 8 && b.subgroups > 0).collect();
    let subgroups: u64 = steady.iter().map(|b| b.subgroups).sum();
    assert!(subgroups > 1000, "{what}: {subgroups} subgroups after iteration 8");
    steady.iter().map(|b| counter(b) * b.subgroups as f64).sum::<f64>() / subgroups as f64
}

/// What slot order is for: regenerating, arrival order scatters the lanes of an intersect
/// subgroup over the pool (every lane its own 64-byte line of path state once refills have
/// shuffled the slots), and slot order brings them back together. Compared over the iterations
/// after the first eight (the refills' steady state), on the intersect pass's coherence counters.
#[test]
fn slot_order_reads_fewer_path_state_lines() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        common::skipped(
            "coherence::slot_order_reads_fewer_path_state_lines",
            "the coherence counters need subgroup operations",
        );
        return;
    }
    let s = RenderSettings { width: 64, height: 48, spp: 16, ..settings(16, false) };
    for compaction in [Compaction::Atomic, Compaction::Scan] {
        let lines = |queue_order| {
            let wf = WavefrontOptions {
                pool_size: Some(PoolSize::Paths(4096)),
                compaction,
                schedule: Schedule::Regenerate,
                queue_order,
                ..Default::default()
            };
            let c = run("rtiow-final", &s, wf, true).unwrap().coherence.unwrap();
            steady_mean(&c, |b| b.lines, &format!("{queue_order:?}"))
        };
        let (arrival, slot) = (lines(QueueOrder::Arrival), lines(QueueOrder::Slot));
        eprintln!("{compaction:?}: lines per intersect subgroup from iteration 8: arrival {arrival:.2}, slot {slot:.2}");
        assert!(slot < 0.75 * arrival, "{compaction:?}: slot order {slot:.2} lines vs arrival {arrival:.2}");
    }
}

/// What the depth key is for: in plain slot order a refill's children, on their first bounce,
/// sit by slot among paths at every depth and from everywhere in the image; keyed by depth they
/// form one run, as in a wave, so an intersect subgroup's lanes come from neighbouring pixels
/// again (pixel spread: the half-perimeter of the box around a subgroup's pixels), and the
/// traversal's lanes diverge less (work-weighted SIMD efficiency of intersect). llvmpipe (8
/// lanes), 24 pools: spread 33.6 → 22.3 and 76.9% → 80.9% with either compaction method, run
/// after run. An H200 (32 lanes): 89.8 → 67.6 with atomics, 83.3 → 67.6 with the scan, and
/// 60% → 64%: 32 lanes of one run already span a row of 32 pixels, so the spread cannot fall
/// as far. A key that did nothing would leave them equal; the bar (0.9×) leaves room for the
/// width and the order a GPU's atomics pick, not for a key that fails.
#[test]
fn the_depth_key_keeps_first_bounces_together() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        common::skipped(
            "coherence::the_depth_key_keeps_first_bounces_together",
            "the coherence counters need subgroup operations",
        );
        return;
    }
    let s = RenderSettings { width: 128, height: 96, spp: 8, ..settings(8, false) };
    for compaction in [Compaction::Atomic, Compaction::Scan] {
        let measure = |queue_order| {
            let wf = WavefrontOptions {
                pool_size: Some(PoolSize::Paths(4096)),
                compaction,
                schedule: Schedule::Regenerate,
                queue_order,
                ..Default::default()
            };
            let out = run("three-spheres", &s, wf, true).unwrap();
            let st = out.schedule.unwrap();
            assert!(st.slot_order, "{queue_order:?}: the run reports slot order");
            assert_eq!(st.depth_key, queue_order == QueueOrder::SlotDepth, "the run reports the key");
            let spread =
                steady_mean(&out.coherence.unwrap(), |b| b.pixel_spread, &format!("{queue_order:?}"));
            (spread, out.simd.unwrap()["work:intersect"].efficiency)
        };
        let ((slot, slot_simd), (depth, depth_simd)) =
            (measure(QueueOrder::Slot), measure(QueueOrder::SlotDepth));
        eprintln!(
            "{compaction:?}: pixel spread per intersect subgroup from iteration 8: slot {slot:.1}, slot-depth {depth:.1}; \
             work:intersect {:.1}% / {:.1}%",
            100.0 * slot_simd,
            100.0 * depth_simd
        );
        assert!(depth < 0.9 * slot, "{compaction:?}: slot-depth spread {depth:.1} vs slot {slot:.1}");
        assert!(depth_simd > slot_simd, "{compaction:?}: work:intersect {depth_simd} vs {slot_simd}");
    }
}

/// `--queue-order auto` (the default) takes slot order only when regenerating a job of at least
/// AUTO_SLOT_POOLS pools with queues, as measured; the run's schedule says which it took.
#[test]
fn auto_order_follows_the_measurement() {
    use wavetrace::options::AUTO_SLOT_POOLS;
    let Some(_) = common::gpu() else { return };
    let s = settings(8, false);
    let samples = 40 * 24 * 8;
    let slot_order = |schedule, compaction, pool: u32| {
        let wf = WavefrontOptions {
            pool_size: Some(PoolSize::Paths(pool)),
            schedule,
            compaction,
            ..Default::default()
        };
        assert_eq!(wf.queue_order, QueueOrder::Auto, "auto is the default");
        run("three-spheres", &s, wf, false).unwrap().schedule.unwrap().slot_order
    };
    let many = (samples / (AUTO_SLOT_POOLS as u32 + 1)).max(1);
    let few = samples / 2;
    assert!(slot_order(Schedule::Regenerate, Compaction::Atomic, many));
    assert!(slot_order(Schedule::Regenerate, Compaction::Scan, many));
    assert!(!slot_order(Schedule::Regenerate, Compaction::Atomic, few), "two pools: arrival");
    assert!(!slot_order(Schedule::Waves, Compaction::Atomic, many), "waves: arrival");
    assert!(!slot_order(Schedule::Regenerate, Compaction::Off, many), "no queues: arrival");
}
