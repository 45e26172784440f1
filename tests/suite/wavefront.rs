//! The wavefront against the megakernel: every knob combination traces the same paths (shared
//! RNG), so images match to rounding; repeat renders are bit-identical; measurements are there.

use crate::common;

use wavetrace::film::Film;
use wavetrace::gpu::timing::Timing;
use wavetrace::gpu::wavefront::{Compaction, Schedule, ShadePasses, Tail, WavefrontOptions};
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::options::PoolSize;
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(spp: u32) -> RenderSettings {
    RenderSettings {
        width: 40,
        height: 24,
        spp,
        max_depth: 12,
        seed: 3,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

fn run(method: Method, scene: &str, s: &RenderSettings, opts: &MethodOptions) -> RenderOutput {
    let scene = builtin::by_name(scene).unwrap();
    render(method, &scene, s, opts, common::gpu(), &|_| {}).unwrap()
}

/// A wavefront render with `wf`, every other option at its default.
fn run_wavefront(scene: &str, s: &RenderSettings, wf: WavefrontOptions) -> RenderOutput {
    run(Method::Wavefront, scene, s, &MethodOptions { wavefront: wf, ..Default::default() })
}

fn all_knobs() -> Vec<WavefrontOptions> {
    let mut v = Vec::new();
    for compaction in [Compaction::Off, Compaction::Atomic, Compaction::Scan] {
        for shade in [ShadePasses::PerMaterial, ShadePasses::Single, ShadePasses::Sorted] {
            if shade == ShadePasses::Sorted && compaction == Compaction::Off {
                continue; // sorted shading needs queues
            }
            // A small pool so every render runs several waves.
            v.push(WavefrontOptions {
                pool_size: Some(PoolSize::Paths(7000)),
                workgroup_size: 64,
                compaction,
                shade,
                ..Default::default()
            });
        }
    }
    v.push(WavefrontOptions { pool_size: None, workgroup_size: 32, ..Default::default() });
    v
}

/// Every knob set of [`all_knobs`], each with one of `cases` in turn: every set runs, and each
/// case meets several sets, at a fraction of the renders of every pairing.
fn knobs_in_turn<T>(cases: &[T]) -> impl Iterator<Item = (&T, WavefrontOptions)> {
    all_knobs().into_iter().enumerate().map(move |(i, knobs)| (&cases[i % cases.len()], knobs))
}

/// The bar: ≥ 99.5% of pixels within 1e-3 relative (per channel), means within 0.1%.
fn assert_match(what: &str, a: &Film, b: &Film) {
    let (frac, mean_diff) = common::same_sample_agreement(a, b, 1e-6);
    eprintln!("{what}: {frac:.4} of pixels within 1e-3, means differ by {mean_diff:.2e}");
    assert!(frac >= 0.995, "{what}: only {frac:.4} of pixels match");
    assert!(mean_diff <= 1e-3, "{what}: means differ by {mean_diff}");
}

/// Both methods trace the same paths, so they trace (nearly) the same number of rays: rounding
/// may send a rare path another way.
fn assert_rays_match(what: &str, a: &Film, b: &Film) {
    let (ra, rb) = (a.rays() as f64, b.rays() as f64);
    assert!(rb >= a.spp as f64 * a.pixels.len() as f64, "{what}: at least one ray per sample");
    assert!((ra - rb).abs() <= 1e-3 * rb, "{what}: {ra} vs {rb} rays");
}

fn matches_megakernel(scene: &str) {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(64);
    let reference = run(Method::Megakernel, scene, &s, &MethodOptions::default()).film;
    for knobs in all_knobs() {
        let opts = MethodOptions { wavefront: knobs, ..Default::default() };
        let out = run(Method::Wavefront, scene, &s, &opts);
        assert_match(&format!("{scene} {knobs:?}"), &out.film, &reference);
        assert_rays_match(&format!("{scene} {knobs:?}"), &out.film, &reference);
    }
}

#[test]
fn wavefront_matches_megakernel_on_three_spheres_for_every_knob() {
    matches_megakernel("three-spheres");
}

#[test]
fn wavefront_matches_megakernel_on_rtiow_final_for_every_knob() {
    matches_megakernel("rtiow-final");
}

/// `--shade per-texture` on the divergence family: a pass per costly pattern traces the
/// megakernel's paths under both schedules and either queue order (the tail too), dispatches one
/// pass per pattern per bounce besides the material kinds' passes for the rest (the checker
/// ground, metal, glass), and needs atomic queues.
#[test]
fn per_texture_shade_passes_trace_the_megakernels_paths() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(4);
    let reference = run(Method::Megakernel, "rtiow-kinds-8", &s, &MethodOptions::default()).film;
    let per_material = run_wavefront("rtiow-kinds-8", &s, WavefrontOptions::default()).film;
    let per_texture = WavefrontOptions {
        shade: ShadePasses::PerTexture,
        pool_size: Some(PoolSize::Paths(2000)),
        ..Default::default()
    };
    let mut opts = MethodOptions { wavefront: per_texture, ..Default::default() };
    opts.wavefront.schedule = Schedule::Waves;
    let waved = run(Method::Wavefront, "rtiow-kinds-8", &s, &opts);
    assert_match("per-texture waves", &waved.film, &reference);
    assert_rays_match("per-texture waves", &waved.film, &reference);
    common::assert_same_paths("per-texture vs per-material", &waved.film, &per_material);
    let t = waved.timings.as_ref().unwrap();
    let waves = s.sample_count().div_ceil(2000);
    let passes = wavetrace::gpu::label::SHADE_BY_PATTERN.iter().chain(&["shade_lambertian", "shade_metal"]);
    for pass in passes {
        assert_eq!(t.passes[*pass].passes, u64::from(s.max_depth) * waves, "{pass} once per bounce and wave");
    }
    use wavetrace::gpu::wavefront::QueueOrder;
    for (order, tail) in [(QueueOrder::Arrival, Tail::Off), (QueueOrder::Slot, Tail::Megakernel)] {
        let wf = regenerating(WavefrontOptions { queue_order: order, tail, ..per_texture });
        let out = run_wavefront("rtiow-kinds-8", &s, wf);
        common::assert_same_paths(
            &format!("per-texture regenerate {order:?} {tail:?}"),
            &out.film,
            &per_material,
        );
    }
    for compaction in [Compaction::Scan, Compaction::Off] {
        assert_refused(WavefrontOptions { compaction, ..per_texture }, "--shade per-texture");
    }
}

#[test]
fn wavefront_matches_on_the_furnace_and_the_linear_loop() {
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { accel: Accel::None, ..settings(8) };
    let mk = run(Method::Megakernel, "furnace", &s, &MethodOptions::default()).film;
    let wf = run(Method::Wavefront, "furnace", &s, &MethodOptions::default()).film;
    assert_match("furnace, accel none", &wf, &mk);
}

#[test]
fn wavefront_repeats_bit_identically_with_atomic_queues() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(8);
    // Atomic appends order queues differently run to run; results must not depend on it.
    let opts = MethodOptions {
        wavefront: WavefrontOptions { pool_size: Some(PoolSize::Paths(3000)), ..Default::default() },
        ..Default::default()
    };
    let a = run(Method::Wavefront, "rtiow-final", &s, &opts);
    let b = run(Method::Wavefront, "rtiow-final", &s, &opts);
    assert!(a.dispatches >= 2, "several waves");
    assert_eq!(a.film, b.film);
}

#[test]
fn measurements_are_reported() {
    let Some(ctx) = common::gpu() else { return };
    let s = settings(4);
    let mut opts = MethodOptions { instrument: true, ..Default::default() };
    opts.wavefront.schedule = Schedule::Waves;
    let out = run(Method::Wavefront, "rtiow-final", &s, &opts);
    let t = out.timings.as_ref().unwrap();
    for label in ["generate", "queue_setup_intersect", "intersect", "queue_setup_shade", "accumulate"] {
        assert!(t.passes.contains_key(label), "pass {label} timed");
    }
    for kind in ["shade_lambertian", "shade_metal", "shade_dielectric"] {
        assert_eq!(t.passes[kind].passes, u64::from(s.max_depth), "{kind} once per bounce");
        assert_eq!(t.per_bounce[kind].len(), s.max_depth as usize);
    }
    assert!(!t.passes.contains_key("shade_emissive"), "only kinds the scene uses are dispatched");
    // Bounce 0 intersects one ray per sample; later bounces no more than that.
    let h = out.histogram.as_ref().unwrap();
    assert_eq!(h.rays[0], s.sample_count());
    assert!(h.rays.windows(2).all(|w| w[1] <= w[0]));
    let shaded: u64 = h.materials.iter().map(|m| m[0]).sum();
    assert!(shaded <= h.rays[0] && shaded > 0);
    // The per-path ray counts summed by the film are the intersect queue's sizes, summed.
    assert_eq!(out.film.rays(), h.rays.iter().sum::<u64>());
    assert!(out.bytes_per_path.unwrap() > 0 && out.pool.unwrap() > 0);
    if ctx.summary.subgroups {
        let simd = out.simd.as_ref().unwrap();
        for pass in ["generate", "intersect", "shade_lambertian"] {
            let e = simd[pass].efficiency;
            assert!(e > 0.0 && e <= 1.0, "{pass}: {e}");
        }
        // generate runs one lane per pool slot, 3840 = 60 workgroups of 64: every subgroup is
        // full, so active lanes equal the lanes the subgroups had, counted per subgroup.
        assert_eq!(out.pool, Some(40 * 24 * 4));
        assert_eq!(simd["generate"].efficiency, 1.0);
        let (min, max) = (u64::from(ctx.summary.subgroup_min_size), u64::from(ctx.summary.subgroup_max_size));
        let groups = simd["generate"].subgroups;
        assert!(
            (3840 / max..=3840 / min.max(1)).contains(&groups),
            "{groups} subgroups of {min}..={max} lanes"
        );
        let mk = run(Method::Megakernel, "rtiow-final", &s, &opts);
        let mk_simd = mk.simd.unwrap();
        // Inside the megakernel's material branches lanes diverge; the wavefront's per-material
        // passes run converged.
        assert!(mk_simd["megakernel_lambertian"].efficiency < simd["shade_lambertian"].efficiency);
    } else {
        common::skipped("wavefront: SIMD efficiency per pass", "the adapter has no subgroup operations");
    }
}

#[test]
fn an_oversized_pool_is_reduced_not_fatal() {
    let Some(ctx) = common::gpu() else { return };
    let opts = MethodOptions {
        wavefront: WavefrontOptions { pool_size: Some(PoolSize::Paths(u32::MAX)), ..Default::default() },
        ..Default::default()
    };
    let out = run(Method::Wavefront, "furnace", &settings(1), &opts);
    // Reduced to exactly the largest pool the adapter's bindings hold, then to the job's sample
    // count (960 here; a render of more than `max` samples to see `max` itself is too slow for
    // the suite): not one path off, not some other fallback such as the default pool.
    let max = wavetrace::gpu::wavefront::max_pool(ctx, WavefrontOptions::default().workgroup_size);
    assert!(max < u32::MAX);
    assert_eq!(out.pool, Some(max.min(40 * 24)));
}

/// `--pool-size device`: Cycles' rule where NVML gives the SM count, else the default pool (as
/// on the software driver), and the run records the count it used, never "device".
#[test]
fn a_pool_sized_to_the_device_follows_cycles_rule_or_the_default() {
    use wavetrace::gpu::wavefront::pool;
    let Some(ctx) = common::gpu() else { return };
    let opts = WavefrontOptions { pool_size: Some(PoolSize::Device), ..Default::default() };
    let max = pool::max_pool(ctx, opts.workgroup_size);
    let sms = wavetrace::gpu::state::GpuMonitor::open(&ctx.summary).and_then(|m| m.multiprocessors());
    let expected = match sms {
        Some(m) => pool::cycles_pool(m).min(max as u64) as u32,
        None => pool::DEFAULT_POOL.min(max),
    };
    assert_eq!(pool::choose(ctx, &opts).unwrap(), expected);
    let out = run(
        Method::Wavefront,
        "furnace",
        &settings(1),
        &MethodOptions { wavefront: opts, ..Default::default() },
    );
    assert_eq!(out.pool, Some(expected.min(40 * 24)));
    let resolved = serde_json::to_value(out.resolved.wavefront).unwrap();
    assert_eq!(resolved["pool_size"], serde_json::json!(expected.min(40 * 24)), "{resolved}");
}

fn regenerating(base: WavefrontOptions) -> WavefrontOptions {
    WavefrontOptions { schedule: Schedule::Regenerate, ..base }
}

/// Path regeneration changes which slot traces which sample and when, never a sample's random
/// numbers or the order the film adds a pixel's samples: its film is the waved film, bit for
/// bit, for every compaction method and shade mode, with and without next-event estimation.
#[test]
fn regenerate_gives_the_waved_film_bit_for_bit() {
    if common::gpu().is_none() {
        return;
    }
    let cases = [
        ("rtiow-final", settings(16)),
        ("cornell", RenderSettings { nee: true, max_depth: 12, ..settings(8) }),
    ];
    // Both scenes' paths (NEE's shadow rays on cornell) across the knob sets.
    for ((scene, s), knobs) in knobs_in_turn(&cases) {
        // A pool of 700 makes chunks of 8 pools: many chunks, many refills per chunk.
        let waves = WavefrontOptions { pool_size: Some(PoolSize::Paths(700)), ..knobs };
        let w = run_wavefront(scene, s, waves);
        let regen = WavefrontOptions { sync_every: 3, ..regenerating(waves) };
        let r = run_wavefront(scene, s, regen);
        assert_eq!(w.film, r.film, "{scene} {regen:?}");
        let stats = r.schedule.as_ref().unwrap();
        assert_eq!(stats.schedule, Schedule::Regenerate);
        assert!(stats.shares > 1, "{scene}: several chunks");
        assert!(r.histogram.is_none(), "queues mix bounces when regenerating");
    }
}

/// A pixel takes at most 4 096 samples per share (the accumulate pass's loop bound), so a tiny
/// image at many samples per pixel is several shares, each with its own ring that wraps: the
/// film is still the waved one, bit for bit.
#[test]
fn regenerate_spans_several_shares() {
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { width: 2, height: 2, spp: 5000, ..settings(1) };
    let base = WavefrontOptions { pool_size: Some(PoolSize::Paths(1000)), ..Default::default() };
    let w = run_wavefront("rtiow-final", &s, base);
    let r = run_wavefront("rtiow-final", &s, regenerating(base));
    assert_eq!(w.film, r.film);
    // Shares of 16 384 and 3 616 samples: 17 and 4 chunks of one pool.
    assert_eq!(r.schedule.unwrap().shares, 21);
}

#[test]
fn regenerate_repeats_bit_identically() {
    if common::gpu().is_none() {
        return;
    }
    let opts = MethodOptions {
        wavefront: regenerating(WavefrontOptions {
            pool_size: Some(PoolSize::Paths(1000)),
            ..Default::default()
        }),
        ..Default::default()
    };
    let a = run(Method::Wavefront, "rtiow-final", &settings(8), &opts);
    let b = run(Method::Wavefront, "rtiow-final", &settings(8), &opts);
    assert_eq!(a.film, b.film);
}

/// The point of regeneration: the intersect passes see a full pool until the chunk's samples
/// run out, where waves see it drain every wave; and far fewer passes are dispatched, fewer of
/// them empty. (Without the tail, the chunk's longest paths still drain it at the end: half the
/// pool on average needs the tail, `the_tail_keeps_occupancy_high_on_small_jobs`.)
#[test]
fn regenerate_keeps_the_pool_full() {
    if common::gpu().is_none() {
        return;
    }
    use wavetrace::gpu::wavefront::QueueOrder;
    // 15 360 samples: 7.5 pools of 2048; paths up to 50 bounces, so that waves wait on their
    // longest paths as the renders do.
    let s = RenderSettings { max_depth: 50, ..settings(16) };
    let base = WavefrontOptions {
        pool_size: Some(PoolSize::Paths(2048)),
        schedule: Schedule::Waves,
        ..Default::default()
    };
    let w = run_wavefront("rtiow-final", &s, base);
    // The schedule alone: slot order (auto's choice on this job) adds one pass an iteration
    // (the atomic method's sweep over the pool), checked below.
    let r = run_wavefront(
        "rtiow-final",
        &s,
        WavefrontOptions { queue_order: QueueOrder::Arrival, ..regenerating(base) },
    );
    let slot = run_wavefront("rtiow-final", &s, regenerating(base)).schedule.unwrap();
    assert!(slot.slot_order);
    let (ws, rs) = (w.schedule.unwrap(), r.schedule.unwrap());
    assert_eq!(slot.dispatches, rs.dispatches + slot.iterations, "{slot:?} vs {rs:?}");
    assert!(slot.dispatches * 3 < ws.dispatches);
    eprintln!("waves: {ws:?}\nregenerate: {rs:?}");
    assert!(rs.intersect_occupancy > 3.0 * ws.intersect_occupancy, "{rs:?} vs {ws:?}");
    assert!(rs.dispatches * 4 < ws.dispatches, "{} vs {} dispatches", rs.dispatches, ws.dispatches);
    assert!(rs.empty_dispatches * 4 < ws.empty_dispatches);
    // Idle iterations come only after a chunk's work ran out, fewer than one check's worth.
    assert!(rs.idle_iterations < rs.shares * rs.sync_every.unwrap() as u64, "{rs:?}");
    assert_eq!(w.dispatches, ws.dispatches);
    assert_eq!(r.empty_dispatches, Some(rs.empty_dispatches));
}

/// Asserts that a wavefront render with `wf` is refused with a message naming `flag`.
#[track_caller]
fn assert_refused(wf: WavefrontOptions, flag: &str) {
    let opts = MethodOptions { wavefront: wf, ..Default::default() };
    let scene = builtin::by_name("furnace").unwrap();
    let e = render(Method::Wavefront, &scene, &settings(1), &opts, common::gpu(), &|_| {}).unwrap_err();
    assert!(format!("{e:#}").contains(flag), "{wf:?}: {e:#}");
}

#[test]
fn bad_sync_every_is_refused() {
    if common::gpu().is_none() {
        return;
    }
    for k in [0, 1025] {
        assert_refused(
            WavefrontOptions { sync_every: k, ..regenerating(Default::default()) },
            "--sync-every",
        );
    }
}

/// `--chunk-pools` (the sample ring's chunks) decides how far refills may run ahead of the
/// oldest unfinished chunk, never what is rendered: with a ring of one chunk (the pool drains
/// at every chunk, as chunks did before the ring) or of eight the film is bit-identical (the
/// accumulate pass adds samples in order either way), and the larger ring keeps the pool fuller,
/// in fewer iterations.
#[test]
fn chunk_pools_change_the_drains_not_the_image() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(8); // 7 680 samples: 7.5 pools of 1024
    let with = |chunk_pools| MethodOptions {
        wavefront: regenerating(WavefrontOptions {
            pool_size: Some(PoolSize::Paths(1024)),
            chunk_pools,
            ..Default::default()
        }),
        ..Default::default()
    };
    let (one, eight) = (
        run(Method::Wavefront, "rtiow-final", &s, &with(1)),
        run(Method::Wavefront, "rtiow-final", &s, &with(8)),
    );
    assert_eq!(one.film, eight.film);
    let (a, b) = (one.schedule.unwrap(), eight.schedule.unwrap());
    assert_eq!((a.shares, b.shares), (8, 8), "chunks of one pool either way");
    assert!(b.iterations < a.iterations && b.intersect_occupancy > a.intersect_occupancy, "{a:?} vs {b:?}");
}

/// With the tail, a ring smaller than the share does not wait for its oldest chunk's longest
/// paths: the tail finishes them once few are left, so refills go on. The film still agrees with
/// the megakernel (the tail is its loop) for every compaction method (the flushed slots leave
/// the queues through intersect), several tails ran, and the pool stays fuller than with the
/// same ring and no tail.
#[test]
fn the_tail_frees_the_sample_ring() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(16); // 15 360 samples: 15 chunks of 1024 in a ring of 2
    let reference = run(Method::Megakernel, "rtiow-final", &s, &MethodOptions::default()).film;
    let ring = |tail, compaction| MethodOptions {
        wavefront: regenerating(WavefrontOptions {
            pool_size: Some(PoolSize::Paths(1024)),
            chunk_pools: 2,
            tail,
            // (Refused without the tail, where it does nothing.)
            tail_threshold: if tail == Tail::Megakernel {
                0.1
            } else {
                WavefrontOptions::default().tail_threshold
            },
            sync_every: 2,
            compaction,
            ..Default::default()
        }),
        ..Default::default()
    };
    for compaction in [Compaction::Atomic, Compaction::Scan, Compaction::Off] {
        let (with, without) = (
            run(Method::Wavefront, "rtiow-final", &s, &ring(Tail::Megakernel, compaction)),
            run(Method::Wavefront, "rtiow-final", &s, &ring(Tail::Off, compaction)),
        );
        let what = format!("ring of 2 with the tail, {compaction:?}");
        assert_match(&what, &with.film, &reference);
        assert_rays_match(&what, &with.film, &reference);
        let (a, b) = (with.schedule.unwrap(), without.schedule.unwrap());
        eprintln!("{what}: {a:?}\nno tail: {b:?}");
        assert!(a.tail_passes > 2 && a.tail_passes <= a.shares, "{what}: {a:?}");
        assert!(a.iterations < b.iterations, "{what}: {a:?} vs {b:?}");
        if compaction != Compaction::Off {
            // (Without queues every intersect pass covers the whole pool.)
            assert!(a.intersect_occupancy > b.intersect_occupancy, "{what}: {a:?} vs {b:?}");
        }
    }
}

#[test]
fn bad_chunk_pools_are_refused() {
    if common::gpu().is_none() {
        return;
    }
    for c in [0, 1025] {
        assert_refused(
            WavefrontOptions { chunk_pools: c, ..regenerating(Default::default()) },
            "--chunk-pools",
        );
    }
    assert_refused(
        WavefrontOptions { chunk_pools: 4, schedule: Schedule::Waves, ..Default::default() },
        "--chunk-pools",
    );
}

/// The megakernel tail finishes a chunk's last paths with the megakernel's own loop: its images
/// agree with the megakernel as the passes do, for every knob, NEE on and off; a threshold of 1
/// hands most paths to it.
#[test]
fn the_megakernel_tail_agrees_with_the_megakernel() {
    if common::gpu().is_none() {
        return;
    }
    let cases = [
        ("rtiow-final", settings(16)),
        ("cornell", RenderSettings { nee: true, max_depth: 12, ..settings(8) }),
    ];
    let cases: Vec<(&str, RenderSettings, Film)> = cases
        .into_iter()
        .map(|(scene, s)| {
            (scene, s.clone(), run(Method::Megakernel, scene, &s, &MethodOptions::default()).film)
        })
        .collect();
    for ((scene, s, reference), knobs) in knobs_in_turn(&cases) {
        for threshold in [0.05, 1.0] {
            let wf = WavefrontOptions {
                pool_size: Some(PoolSize::Paths(2000)),
                tail: Tail::Megakernel,
                tail_threshold: threshold,
                sync_every: 2,
                ..regenerating(knobs)
            };
            let out = run_wavefront(scene, s, wf);
            let what = format!("{scene} {wf:?}");
            assert_match(&what, &out.film, reference);
            assert_rays_match(&what, &out.film, reference);
            let stats = out.schedule.unwrap();
            assert!(stats.tail_passes <= stats.shares, "{what}: at most one tail per chunk");
            if threshold == 1.0 {
                // Due as soon as a chunk's samples have all started.
                assert!(stats.tail_passes >= 1 && stats.tail_paths > 0, "{what}: {stats:?}");
                assert!(out.timings.unwrap().passes.contains_key("tail"));
            }
        }
    }
}

/// With the tail, the passes stop when the pool drains: the bar of half the pool
/// occupied on average holds even for a job of two pools.
#[test]
fn the_tail_keeps_occupancy_high_on_small_jobs() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(4); // 3 840 samples: 1.9 pools of 2 000
    let wf = WavefrontOptions {
        pool_size: Some(PoolSize::Paths(2000)),
        tail: Tail::Megakernel,
        tail_threshold: 0.25,
        sync_every: 1,
        ..regenerating(Default::default())
    };
    let out = run_wavefront("rtiow-final", &s, wf);
    let stats = out.schedule.unwrap();
    eprintln!("{stats:?}");
    assert!(stats.intersect_occupancy >= 0.5, "{stats:?}");
}

/// With the tail, once every sample has started the host checks after every iteration, so the
/// tail starts in the iteration it is due whatever `--sync-every`: as many iterations as with a
/// check after each, none idle, and for a job within one pool fewer than one batch of 8.
#[test]
fn the_tail_starts_in_the_iteration_it_is_due() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(16); // 15 360 samples: one pool
    for compaction in [Compaction::Atomic, Compaction::Scan] {
        let wf = |k| WavefrontOptions {
            compaction,
            tail: Tail::Megakernel,
            sync_every: k,
            ..regenerating(Default::default())
        };
        let each = run_wavefront("three-spheres", &s, wf(1));
        let batched = run_wavefront("three-spheres", &s, wf(8));
        assert_eq!(batched.film, each.film, "{compaction:?}");
        let (a, b) = (each.schedule.unwrap(), batched.schedule.unwrap());
        eprintln!("{compaction:?}: every iteration {a:?}\nbatches of 8 {b:?}");
        assert_eq!(b.iterations, a.iterations, "{compaction:?}");
        assert_eq!(b.idle_iterations, 0, "{compaction:?}");
        assert_eq!(b.tail_passes, 1, "{compaction:?}");
        assert!(b.iterations < 8, "{compaction:?}: {b:?}");
    }
}

#[test]
fn a_tail_needs_regeneration() {
    if common::gpu().is_none() {
        return;
    }
    assert_refused(
        WavefrontOptions { tail: Tail::Megakernel, schedule: Schedule::Waves, ..Default::default() },
        "--schedule regenerate",
    );
    for t in [0.0, -0.5, 1.5, f64::NAN] {
        let wf = WavefrontOptions {
            tail: Tail::Megakernel,
            tail_threshold: t,
            ..regenerating(Default::default())
        };
        assert_refused(wf, "--tail-threshold");
    }
}

/// `--timing frame` drops the per-pass timestamps: the same image, every pass still counted,
/// the whole time under `frame` from the host clock; for both GPU methods.
#[test]
fn frame_timing_counts_passes_and_times_the_frame() {
    if common::gpu().is_none() {
        return;
    }
    use wavetrace::gpu::timing::{TimeSource, Timing, FRAME_LABEL};
    let s = settings(4);
    for method in [Method::Megakernel, Method::Wavefront] {
        let passes = run(method, "rtiow-final", &s, &MethodOptions::default());
        let frame =
            run(method, "rtiow-final", &s, &MethodOptions { timing: Timing::Frame, ..Default::default() });
        assert_eq!(passes.film, frame.film, "{method:?}");
        let (p, f) = (passes.timings.unwrap(), frame.timings.unwrap());
        assert_eq!(f.source, TimeSource::WallClock);
        assert!(f.passes[FRAME_LABEL].seconds > 0.0, "{method:?}");
        for (label, t) in &p.passes {
            assert_eq!(f.passes[label].passes, t.passes, "{method:?} {label}: same passes counted");
            assert_eq!(f.passes[label].seconds, 0.0, "{method:?} {label}: timed only as a frame");
        }
        assert_eq!(frame.dispatches, passes.dispatches);
    }
}

/// The subgroup scan computes the same prefix sums as the workgroup scan, so the queues it builds
/// are the same, in the same order: the films are bit-identical (and match the megakernel as
/// every knob does, `all_knobs` running the default, subgroups where the adapter has them).
#[test]
fn the_subgroup_scan_builds_the_same_queues() {
    let Some(ctx) = common::gpu() else { return };
    use wavetrace::gpu::wavefront::Scan;
    let s = RenderSettings { nee: true, max_depth: 12, ..settings(8) };
    for schedule in [Schedule::Waves, Schedule::Regenerate] {
        let with = |scan| {
            let wf = WavefrontOptions {
                pool_size: Some(PoolSize::Paths(3000)),
                compaction: Compaction::Scan,
                schedule,
                scan,
                ..Default::default()
            };
            let out = run_wavefront("cornell", &s, wf);
            (out.film, out.schedule.unwrap().subgroup_scan)
        };
        let (workgroup, used) = with(Scan::Workgroup);
        assert_eq!(used, Some(false));
        if ctx.summary.subgroups {
            let (subgroup, used) = with(Scan::Subgroup);
            assert_eq!(used, Some(true));
            assert_eq!(subgroup, workgroup, "{schedule:?}");
        } else {
            common::skipped("wavefront: the subgroup scan's film", "the adapter has no subgroup operations");
        }
    }
}

/// Subgroup-aggregated appends reserve the same entries as per-lane atomics, only in a different
/// order within a queue; the ring makes the film independent of that order, so films are
/// bit-identical on every schedule and tail (instrumented too: its own shader variant).
#[test]
fn subgroup_appends_give_the_same_film() {
    use wavetrace::gpu::wavefront::Append;
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        common::skipped(
            "wavefront::subgroup_appends_give_the_same_film",
            "the adapter has no subgroup operations",
        );
        return;
    }
    let s = RenderSettings { nee: true, max_depth: 12, ..settings(8) };
    let cases = [
        (Schedule::Waves, Tail::Off, false),
        (Schedule::Regenerate, Tail::Off, false),
        (Schedule::Regenerate, Tail::Megakernel, false),
        (Schedule::Waves, Tail::Off, true),
    ];
    for (schedule, tail, instrument) in cases {
        let with = |append| {
            let wf = WavefrontOptions {
                pool_size: Some(PoolSize::Paths(3000)),
                schedule,
                tail,
                append,
                ..Default::default()
            };
            let opts = MethodOptions { wavefront: wf, instrument, ..Default::default() };
            let out = run(Method::Wavefront, "cornell", &s, &opts);
            (out.film, out.schedule.unwrap().subgroup_append)
        };
        let (lane, used) = with(Append::Lane);
        assert!(!used);
        let (subgroup, used) = with(Append::Subgroup);
        assert!(used);
        assert!(lane.image_mean() > 0.0, "{schedule:?}: a black film proves nothing");
        assert_eq!(subgroup, lane, "{schedule:?} {tail:?} instrument={instrument}");
        let (auto, used) = with(Append::Auto);
        assert!(used, "auto takes subgroups where the adapter has them");
        assert_eq!(auto, lane);
    }
}

/// The scan's block pass runs one workgroup per 1,024 blocks of 256 positions, each starting from
/// the sum of the blocks before its own: with a pool of three such groups (queues that cross group
/// boundaries), the scan builds queues holding the same paths as the atomic appends, so the films
/// and the queue sizes per bounce are the same, with either workgroup scan.
#[test]
fn the_scan_spans_block_groups() {
    use wavetrace::gpu::wavefront::Scan;
    let Some(ctx) = common::gpu() else { return };
    let s = RenderSettings { width: 128, height: 96, spp: 48, max_depth: 3, ..settings(1) };
    let pool = 128 * 96 * 48;
    assert!(pool > 2 * 1024 * 256, "three groups of blocks");
    let with = |compaction, scan| {
        let wf = WavefrontOptions {
            pool_size: Some(PoolSize::Paths(pool)),
            compaction,
            scan,
            schedule: Schedule::Waves,
            ..Default::default()
        };
        let out = run_wavefront("cornell", &s, wf);
        assert_eq!(out.pool, Some(pool));
        (out.film, out.histogram.unwrap())
    };
    let (atomic, atomic_sizes) = with(Compaction::Atomic, Scan::Auto);
    assert!(atomic.image_mean() > 0.0);
    let mut scans = vec![Scan::Workgroup];
    if ctx.summary.subgroups {
        scans.push(Scan::Subgroup);
    }
    for scan in scans {
        let (film, sizes) = with(Compaction::Scan, scan);
        assert_eq!(sizes, atomic_sizes, "{scan:?}: queue sizes per bounce");
        assert_eq!(film, atomic, "{scan:?}");
    }
}

/// The pool holds only what the render's passes read: the shadow ray and weight with a shadow
/// pass (NEE on, a scene with lights), the scan's scratch with the scan compaction, each slot's
/// queue target alone for slot order's sweep (atomic appends), each slot's sample when
/// regenerating; unused buffers are one 16-byte element. `bytes_per_path` says the same.
#[test]
fn pool_memory_follows_the_knobs() {
    if common::gpu().is_none() {
        return;
    }
    use wavetrace::gpu::wavefront::QueueOrder::{self, Arrival};
    let pool = 1000u64;
    let memory = |nee: bool, compaction: Compaction, schedule: Schedule, queue_order: QueueOrder| {
        let s = RenderSettings { nee, ..settings(2) };
        let opts = MethodOptions {
            wavefront: WavefrontOptions {
                pool_size: Some(PoolSize::Paths(pool as u32)),
                compaction,
                schedule,
                queue_order,
                ..Default::default()
            },
            ..Default::default()
        };
        let out = run(Method::Wavefront, "cornell", &s, &opts);
        let m = out.memory.unwrap().by_category;
        (out.bytes_per_path.unwrap(), m["shadow_queue"], m["queues"], m["path_state"])
    };
    let (plain, plain_shadow, plain_queues, plain_state) =
        memory(false, Compaction::Atomic, Schedule::Waves, Arrival);
    assert_eq!(plain, 4 * 16 + 8 * 4, "state and eight queue entries");
    assert_eq!(plain_shadow, 2 * 16, "no shadow pass: placeholders only");
    let (nee, nee_shadow, _, _) = memory(true, Compaction::Atomic, Schedule::Waves, Arrival);
    assert_eq!(nee, plain + 32);
    assert_eq!(nee_shadow, pool * 32, "shadow ray and weight per slot");
    let (scan, _, scan_queues, _) = memory(false, Compaction::Scan, Schedule::Waves, Arrival);
    assert_eq!(scan, plain + 12);
    // Scratch per slot, a total and a prefix sum per block of 256 positions.
    let block_sums = 2 * pool.div_ceil(256) * 16;
    assert_eq!(scan_queues - plain_queues, pool * 12 + block_sums - 4 * 16, "scan scratch");
    let (regen, _, regen_queues, regen_state) =
        memory(false, Compaction::Atomic, Schedule::Regenerate, Arrival);
    assert_eq!(regen, plain + 8);
    assert_eq!(regen_state - plain_state, pool * 8 - 16, "each slot's sample and bounce");
    let (sweep, _, sweep_queues, _) =
        memory(false, Compaction::Atomic, Schedule::Regenerate, QueueOrder::Slot);
    assert_eq!(sweep, regen + 4, "slot order's sweep: each slot's queue target");
    assert_eq!(sweep_queues - regen_queues, pool * 4 - 16, "the targets, no scan scratch");
    // Without lights, NEE has nothing to sample: no shadow pass, no shadow buffers.
    let s = RenderSettings { nee: true, ..settings(2) };
    let out = run(Method::Wavefront, "three-spheres", &s, &MethodOptions::default());
    assert_eq!(out.memory.unwrap().by_category["shadow_queue"], 2 * 16);
}

/// `--schedule auto` (the default) takes what measured faster on the adapter's kind: regenerate
/// with the megakernel tail on a GPU, waves on a software adapter (README); a named schedule
/// stays as named, the megakernel's auto is its naive form, and a render reports what it took.
#[test]
fn auto_schedule_follows_the_adapter_kind() {
    let Some(ctx) = common::gpu() else { return };
    let kind = |device_type: &str| wavetrace::gpu::context::AdapterSummary {
        device_type: device_type.into(),
        ..ctx.summary.clone()
    };
    let (gpu, software) = (kind("DiscreteGpu"), kind("Cpu"));
    let auto = WavefrontOptions { schedule: Schedule::Auto, ..Default::default() };
    let on_gpu = auto.resolve(gpu.is_software()).options;
    assert_eq!((on_gpu.schedule, on_gpu.tail), (Schedule::Regenerate, Tail::Megakernel));
    assert!(!kind("IntegratedGpu").is_software());
    let on_software = auto.resolve(software.is_software()).options;
    assert_eq!((on_software.schedule, on_software.tail), (Schedule::Waves, Tail::Off));
    for named in [Schedule::Waves, Schedule::Regenerate] {
        let o = WavefrontOptions { schedule: named, ..auto }.resolve(gpu.is_software()).options;
        assert_eq!((o.schedule, o.tail), (named, Tail::Off), "{named:?}");
    }
    let mk = wavetrace::gpu::megakernel::MegakernelOptions { schedule: Schedule::Auto, ..Default::default() };
    assert_eq!(mk.resolve().schedule, Schedule::Waves);

    let out = run_wavefront("three-spheres", &settings(2), auto);
    let (want, tail) =
        if ctx.summary.is_software() { (Schedule::Waves, 0) } else { (Schedule::Regenerate, 1) };
    let st = out.schedule.unwrap();
    assert_eq!(st.schedule, want);
    assert!(st.tail_passes >= tail, "{st:?}");
    // What the run's report records: the schedule that ran, not "auto".
    let opts = MethodOptions { wavefront: auto, ..Default::default() };
    assert_eq!(opts.resolve(Method::Wavefront, Some(ctx.summary.is_software())).wavefront.schedule, want);
}

/// `--compute-passes shared` (issue 42): consecutive dispatches share a compute pass where no
/// per-pass timestamps need their own. wgpu still orders each dispatch's storage use inside a
/// pass, so the film is the waves' (the tail's paths, where it runs) for every schedule, from
/// fewer compute passes; with per-pass timestamps the knob changes nothing.
#[test]
fn shared_compute_passes_give_the_same_film_from_fewer_passes() {
    use wavetrace::gpu::wavefront::ComputePasses;
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { nee: true, ..settings(4) };
    let frame = |wf: WavefrontOptions| {
        let opts = MethodOptions { wavefront: wf, timing: Timing::Frame, ..Default::default() };
        run(Method::Wavefront, "cornell", &s, &opts)
    };
    let waves = WavefrontOptions {
        schedule: Schedule::Waves,
        pool_size: Some(PoolSize::Paths(1024)),
        ..Default::default()
    };
    let regenerate = WavefrontOptions { schedule: Schedule::Regenerate, sync_every: 2, ..waves };
    let tail = WavefrontOptions { tail: Tail::Megakernel, ..regenerate };
    let reference = frame(waves).film;
    for (name, wf) in [("waves", waves), ("regenerate", regenerate), ("regenerate+tail", tail)] {
        let each = frame(WavefrontOptions { compute_passes: ComputePasses::PerDispatch, ..wf });
        // Shared passes are the default.
        let shared = frame(wf);
        assert_eq!(each.compute_passes, Some(each.dispatches), "{name}: a pass per dispatch");
        // Regenerating, the host submits a batch of --sync-every iterations at a time (and
        // waits only at the share's end: issue 42).
        let submissions = each.timings.as_ref().unwrap().submissions;
        assert!(
            submissions >= if wf.schedule == Schedule::Regenerate { 2 } else { 1 },
            "{name}: {submissions}"
        );
        assert_eq!(shared.dispatches, each.dispatches, "{name}: the same dispatches");
        let passes = shared.compute_passes.unwrap();
        assert!(
            passes * 2 < shared.dispatches,
            "{name}: {passes} passes for {} dispatches",
            shared.dispatches
        );
        common::assert_waves_film(name, &shared.film, &reference, wf.tail);
        common::assert_waves_film(name, &each.film, &reference, wf.tail);
    }
    // With per-pass timestamps each dispatch keeps its pass.
    if common::gpu().unwrap().summary.timestamps {
        let opts = MethodOptions {
            wavefront: WavefrontOptions { compute_passes: ComputePasses::Shared, ..waves },
            timing: Timing::Passes,
            ..Default::default()
        };
        let timed = run(Method::Wavefront, "cornell", &s, &opts);
        assert_eq!(timed.compute_passes, Some(timed.dispatches));
    }
}

/// `--shade sorted` (issue 42, Cycles' way): one pass over the material queues end to end shades
/// every hit the per-material passes shade, so the film is theirs bit for bit, on both schedules,
/// with NEE, in fewer dispatches: one shade pass per iteration where per-material records one
/// per kind the scene uses. Without queues it is refused.
#[test]
fn sorted_shading_gives_the_per_material_film_in_one_pass() {
    if common::gpu().is_none() {
        return;
    }
    // rtiow-final's kinds: lambertian, metal, dielectric.
    let kinds = 3;
    for (name, s, base) in [
        (
            "waves",
            settings(8),
            WavefrontOptions { pool_size: Some(PoolSize::Paths(2000)), ..Default::default() },
        ),
        (
            "regenerate+tail",
            RenderSettings { nee: true, ..settings(8) },
            WavefrontOptions { tail: Tail::Megakernel, sync_every: 3, ..regenerating(Default::default()) },
        ),
    ] {
        let per_material = run_wavefront("rtiow-final", &s, base);
        let sorted =
            run_wavefront("rtiow-final", &s, WavefrontOptions { shade: ShadePasses::Sorted, ..base });
        assert_eq!(sorted.film, per_material.film, "{name}");
        let iterations = per_material.schedule.as_ref().unwrap().iterations;
        assert_eq!(sorted.schedule.as_ref().unwrap().iterations, iterations, "{name}");
        assert_eq!(sorted.dispatches + (kinds - 1) * iterations, per_material.dispatches, "{name}");
        let passes: Vec<&str> = sorted.timings.as_ref().unwrap().passes.keys().copied().collect();
        assert!(passes.contains(&"shade_sorted"), "{name}: {passes:?}");
        assert!(!passes.iter().any(|p| p.starts_with("shade_l")), "{name}: {passes:?}");
    }
    assert_refused(
        WavefrontOptions { shade: ShadePasses::Sorted, compaction: Compaction::Off, ..Default::default() },
        "--shade",
    );
}

/// `--shadow-rays inline` (issue 44): shade traces each shadow ray it samples, as the megakernel
/// does, instead of queuing it for the shadow pass; the film is the shadow pass's bit for bit on
/// both schedules, with the roulette, in slot order and with the scan; no shadow pass runs, the
/// shadow rays are counted all the same (the traffic model's items), and the pool holds no shadow
/// ray or weight. Without queues it is refused.
#[test]
fn inline_shadow_rays_give_the_shadow_pass_film() {
    use wavetrace::gpu::wavefront::{QueueOrder, ShadowRays};
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { nee: true, ..settings(4) };
    let waves = WavefrontOptions { pool_size: Some(PoolSize::Paths(1024)), ..Default::default() };
    let tail = WavefrontOptions { tail: Tail::Megakernel, sync_every: 2, ..regenerating(waves) };
    let slot = WavefrontOptions { queue_order: QueueOrder::Slot, ..tail };
    let scan = WavefrontOptions { compaction: Compaction::Scan, ..tail };
    for (name, wf, roulette) in [
        ("waves", waves, false),
        ("regenerate+tail", tail, true),
        ("slot order", slot, false),
        ("scan", scan, false),
    ] {
        let s = RenderSettings { roulette, ..s.clone() };
        let pass = run_wavefront("cornell", &s, wf);
        let inline = run_wavefront("cornell", &s, WavefrontOptions { shadow_rays: ShadowRays::Inline, ..wf });
        assert_eq!(inline.film, pass.film, "{name}");
        let passes: Vec<&str> = inline.timings.as_ref().unwrap().passes.keys().copied().collect();
        assert!(!passes.contains(&"shadow"), "{name}: {passes:?}");
        let shadow_items = |r: &RenderOutput| {
            let t = r.schedule.as_ref().unwrap().state_traffic.as_ref().unwrap();
            t.passes.iter().find(|p| p.label == "shadow").map(|p| p.items)
        };
        let queued = shadow_items(&pass).expect("the shadow pass's items");
        assert!(queued > 0, "{name}");
        assert_eq!(shadow_items(&inline), None, "{name}");
        assert_eq!(
            inline.schedule.as_ref().unwrap().queued,
            pass.schedule.as_ref().unwrap().queued,
            "{name}"
        );
        assert!(inline.bytes_per_path < pass.bytes_per_path, "{name}");
    }
    assert_refused(
        WavefrontOptions {
            shadow_rays: ShadowRays::Inline,
            compaction: Compaction::Off,
            ..Default::default()
        },
        "--shadow-rays",
    );
}

/// `--refill in-place` (issue 44: generate fused into the passes where paths end): a slot whose
/// path escapes in intersect or ends in shade takes the share's next sample there and then. It
/// changes which slot traces which sample and when, never a sample's random numbers or the film's
/// order: the film is the refill pass's bit for bit, with the tail (also one that runs as soon as
/// every sample has started, and so meets camera rays just queued by refills in place), NEE and the roulette, a sample ring of two pools (claims past its
/// fill limit fail and go to the free list), stored camera rays (the ray sort), pool-size
/// launches, sorted shading, inline shadow rays, either kind of ticket (per lane, per subgroup),
/// and slot order (the sweep, and the depth key's scan, queue the refilled slots the passes
/// marked). Both passes refill, the refill pass starts fewer samples, and the modelled state
/// traffic falls. What it cannot run with is refused.
#[test]
fn refills_in_place_give_the_refill_pass_film() {
    use wavetrace::gpu::wavefront::{Append, CompactStates, Launch, QueueOrder, RaySort, Refill, ShadowRays};
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { nee: true, ..settings(4) };
    let base =
        regenerating(WavefrontOptions { pool_size: Some(PoolSize::Paths(1024)), ..Default::default() });
    let tail = WavefrontOptions { tail: Tail::Megakernel, sync_every: 2, ..base };
    for (name, scene, wf, roulette) in [
        ("regenerate", "cornell", base, false),
        ("regenerate+tail", "cornell", tail, true),
        ("two-pool ring", "rtiow-final", WavefrontOptions { chunk_pools: 2, ..tail }, false),
        // The tail as soon as every sample has started: it finishes camera rays just queued.
        ("eager tail", "cornell", WavefrontOptions { tail_threshold: 1.0, sync_every: 1, ..tail }, false),
        ("lane tickets", "cornell", WavefrontOptions { append: Append::Lane, ..base }, false),
        ("ray sort", "cornell", WavefrontOptions { ray_sort: RaySort::Octant, ..tail }, false),
        ("pool launches", "cornell", WavefrontOptions { launch: Launch::Pool, ..tail }, false),
        ("sorted shade", "rtiow-final", WavefrontOptions { shade: ShadePasses::Sorted, ..tail }, false),
        ("inline shadows", "cornell", WavefrontOptions { shadow_rays: ShadowRays::Inline, ..tail }, true),
        ("slot order", "cornell", WavefrontOptions { queue_order: QueueOrder::Slot, ..tail }, true),
        ("slot-depth", "rtiow-final", WavefrontOptions { queue_order: QueueOrder::SlotDepth, ..tail }, false),
        (
            "slot order, stored rays",
            "cornell",
            WavefrontOptions { queue_order: QueueOrder::Slot, ray_sort: RaySort::Octant, ..base },
            false,
        ),
    ] {
        let s = RenderSettings { roulette, ..s.clone() };
        let pass = run_wavefront(scene, &s, wf);
        let fused = run_wavefront(scene, &s, WavefrontOptions { refill: Refill::InPlace, ..wf });
        assert_eq!(fused.film, pass.film, "{name}");
        let stats = fused.schedule.as_ref().unwrap();
        let refilled = stats.refilled_in_place.expect("counted");
        assert!(refilled.intersect > 0 && refilled.shade > 0, "{name}: {refilled:?}");
        assert_eq!(pass.schedule.as_ref().unwrap().refilled_in_place, None, "{name}");
        let traffic = |r: &RenderOutput| r.schedule.as_ref().unwrap().state_traffic.clone().unwrap();
        let items = |r: &RenderOutput| {
            traffic(r).passes.iter().find(|p| p.label == "regenerate").map(|p| p.items).unwrap()
        };
        let samples = s.sample_count();
        assert_eq!(items(&pass), samples, "{name}");
        assert_eq!(items(&fused), samples - refilled.intersect - refilled.shade, "{name}");
        assert!(traffic(&fused).bytes_per_sample < traffic(&pass).bytes_per_sample, "{name}");
    }
    let fused = WavefrontOptions { refill: Refill::InPlace, ..base };
    for (wf, flag) in [
        (WavefrontOptions { schedule: Schedule::Waves, ..fused }, "--schedule regenerate"),
        (WavefrontOptions { compaction: Compaction::Scan, ..fused }, "--compaction-method atomic"),
        (WavefrontOptions { refill_below: 0.5, ..fused }, "--refill-below 1"),
        (WavefrontOptions { compact_states: CompactStates::On, ..fused }, "--compact-states off"),
    ] {
        assert_refused(wf, flag);
    }
}

/// `--launch pool` (issue 42, pbrt-v4's way): the passes that consume a queue launched at the
/// pool's size, threads past the queue returning, give the films of indirect launches bit for bit
/// and the same counts, on every schedule, with NEE's shadow pass, other queue orders, and
/// iterations recorded past a share's end (which pool-size launches run and must do nothing in).
#[test]
fn pool_launches_give_the_indirect_films_and_counts() {
    use wavetrace::gpu::wavefront::{Launch, QueueOrder};
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { nee: true, ..settings(4) };
    let waves = WavefrontOptions {
        schedule: Schedule::Waves,
        pool_size: Some(PoolSize::Paths(1024)),
        ..Default::default()
    };
    let regenerate = WavefrontOptions { schedule: Schedule::Regenerate, sync_every: 2, ..waves };
    let tail = WavefrontOptions { tail: Tail::Megakernel, ..regenerate };
    // Past the end: a job of one pool ends inside the first batch of 24 iterations.
    let ahead = WavefrontOptions { sync_every: 24, pool_size: None, ..tail };
    let slot = WavefrontOptions { queue_order: QueueOrder::Slot, ..tail };
    let scan = WavefrontOptions { compaction: Compaction::Scan, ..regenerate };
    let reference = run_wavefront("cornell", &s, waves).film;
    for (name, wf) in [
        ("waves", waves),
        ("regenerate", regenerate),
        ("regenerate+tail", tail),
        ("regenerate+tail, batches of 24", ahead),
        ("regenerate+tail, slot order", slot),
        ("regenerate, scan", scan),
    ] {
        let indirect = run_wavefront("cornell", &s, wf);
        let pool = run_wavefront("cornell", &s, WavefrontOptions { launch: Launch::Pool, ..wf });
        assert_eq!(pool.film, indirect.film, "{name}");
        common::assert_waves_film(name, &pool.film, &reference, wf.tail);
        assert_eq!(pool.dispatches, indirect.dispatches, "{name}");
        let (a, b) = (indirect.schedule.unwrap(), pool.schedule.unwrap());
        assert_eq!(
            (b.iterations, b.empty_dispatches, b.tail_paths, b.speculative_iterations > 0),
            (a.iterations, a.empty_dispatches, a.tail_paths, a.speculative_iterations > 0),
            "{name}: {a:?} vs {b:?}"
        );
        assert_eq!(pool.resolved.wavefront.launch, Launch::Pool, "{name}: recorded as it ran");
    }
}

/// `--shader-checks unchecked` (issue 44): without wgpu's runtime checks every GPU method gives
/// the film it gives with them, bit for bit (the checks change no arithmetic, and no access of
/// ours leaves its array: were one to, unchecked would be undefined behaviour), for both
/// megakernels and the wavefront's schedules, with NEE.
#[test]
fn unchecked_shaders_give_the_checked_films() {
    use wavetrace::gpu::shader_checks::ShaderChecks;
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { nee: true, ..settings(2) };
    for (method, opts) in common::gpu_ways() {
        let checked = run(method, "cornell", &s, &opts);
        let unchecked = run(
            method,
            "cornell",
            &s,
            &MethodOptions { shader_checks: ShaderChecks::Unchecked, ..opts.clone() },
        );
        assert_eq!(checked.film, unchecked.film, "{method:?} {:?}", opts);
    }
}

/// Waves never wait inside a frame (issue 42): without per-pass timestamps the host submits wave
/// after wave and reads their counters once, from the share ledger, after the last; the counts
/// and the film are those of a render that waits after every wave (per-pass timing), and the
/// histogram holds every path's camera ray. With more waves than the ledger holds, the host
/// reads it once more, mid-frame.
#[test]
fn waves_never_wait_inside_the_frame_and_count_the_same() {
    use wavetrace::gpu::wavefront::share_ledger::SLOTS;
    let Some(ctx) = common::gpu() else { return };
    let small = RenderSettings { width: 20, height: 12, spp: 4, max_depth: 2, ..settings(4) };
    for (s, pool) in [(RenderSettings { max_depth: 8, ..settings(8) }, 64), (small, 1)] {
        let paths = (s.width * s.height * s.spp) as u64;
        let waves = paths.div_ceil(pool);
        let wf = WavefrontOptions {
            schedule: Schedule::Waves,
            pool_size: Some(PoolSize::Paths(pool as u32)),
            ..Default::default()
        };
        let render = |timing| {
            run(
                Method::Wavefront,
                "three-spheres",
                &s,
                &MethodOptions { wavefront: wf, timing, ..Default::default() },
            )
        };
        let (frame, passes) = (render(Timing::Frame), render(Timing::Passes));
        let t = frame.timings.as_ref().unwrap();
        assert_eq!(t.submissions, waves, "pool {pool}: one submission per wave");
        assert_eq!(
            t.waits,
            waves.div_ceil(SLOTS),
            "pool {pool}: the host waits only when the ledger is full and at the end"
        );
        if ctx.summary.timestamps {
            assert!(
                passes.timings.as_ref().unwrap().waits >= waves,
                "per-pass timing waits after every wave"
            );
        }
        // The same counts (the traffic model's passes have times only where passes are timed).
        let untimed = |o: &RenderOutput| {
            let mut s = o.schedule.clone().unwrap();
            for p in s.state_traffic.iter_mut().flat_map(|t| t.passes.iter_mut()) {
                (p.seconds, p.bytes_per_second) = (None, None);
            }
            s
        };
        assert_eq!(untimed(&frame), untimed(&passes), "pool {pool}: the same counts");
        assert_eq!(frame.schedule.as_ref().unwrap().iterations, waves * s.max_depth as u64);
        let h = frame.histogram.as_ref().unwrap();
        assert_eq!(Some(h), passes.histogram.as_ref(), "pool {pool}: the same histogram");
        assert_eq!(h.rays[0], paths, "pool {pool}: every path's camera ray at bounce 0");
        let bits = |f: &wavetrace::film::Film| f.mean_rgb().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&frame.film), bits(&passes.film), "pool {pool}: the same film");
    }
}

/// Issue 42: the regenerating host loop never waits inside a share. The GPU decides after each
/// check (schedule_decide); the host submits batches ahead and reads their counters back through
/// a ring of staging buffers it polls, so the only wait is the share's end: one per share, no
/// read-back that found the GPU idle, with and without the tail, in one chunk or many, with a
/// ring of one or two chunks.
#[test]
fn the_regenerating_host_never_waits_inside_a_share() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(8); // 7 680 samples
    for tail in [Tail::Off, Tail::Megakernel] {
        for (pool, chunk_pools) in [
            (None, 8),
            (Some(PoolSize::Paths(700)), 8),
            (Some(PoolSize::Paths(700)), 2),
            (Some(PoolSize::Paths(1024)), 1),
        ] {
            let wf = WavefrontOptions {
                pool_size: pool,
                chunk_pools,
                tail,
                sync_every: 2,
                ..regenerating(Default::default())
            };
            let opts = MethodOptions { wavefront: wf, timing: Timing::Frame, ..Default::default() };
            let out = run(Method::Wavefront, "rtiow-final", &s, &opts);
            let (stats, timings) = (out.schedule.unwrap(), out.timings.unwrap());
            let what =
                format!("{wf:?}: {stats:?}, {} submissions, {} waits", timings.submissions, timings.waits);
            assert_eq!(stats.blocking_reads, 0, "{what}");
            assert_eq!(timings.waits, 1, "{what}: one share, one wait at its end");
            if pool.is_some() {
                assert!(
                    stats.shares > 1 && timings.submissions > 2,
                    "{what}: several chunks, several batches"
                );
            }
            if tail == Tail::Megakernel {
                assert!(stats.tail_passes >= 1, "{what}");
            }
            // One batch in flight: the host waits for each check's read-back, the GPU idle (the
            // loop before the GPU decided, kept as the device's A/B); the film is the same.
            if pool.is_some() {
                let one = WavefrontOptions { batches_in_flight: 1, ..wf };
                let waited =
                    run(Method::Wavefront, "rtiow-final", &s, &MethodOptions { wavefront: one, ..opts });
                let st = waited.schedule.as_ref().unwrap();
                assert!(st.blocking_reads > 0 && st.throttles == 0, "{what}: {st:?}");
                assert_eq!(waited.film, out.film, "{what}: one batch in flight, the same film");
                let timings = waited.timings.unwrap();
                assert_eq!(timings.waits, st.blocking_reads + 1, "{what}: each read waited for, and the end");
            }
        }
    }
    let bad = WavefrontOptions { batches_in_flight: 0, ..regenerating(Default::default()) };
    let err = render(
        Method::Wavefront,
        &builtin::by_name("rtiow-final").unwrap(),
        &s,
        &MethodOptions { wavefront: bad, ..Default::default() },
        common::gpu(),
        &|_| {},
    )
    .expect_err("0 batches in flight is refused");
    assert!(err.to_string().contains("--batches-in-flight must be in 1..="), "{err}");
}

/// The iterations the host records past a share's end (it has not yet read that the share is
/// done) dispatch zero workgroups: however far ahead the host runs — batches of 1 iteration or
/// of 24, three in flight — the film is the waved one, bit for bit, and the share's own counts
/// (iterations, dispatches, empty ones, tail passes) are those of a host one batch ahead.
#[test]
fn speculative_iterations_change_no_film() {
    if common::gpu().is_none() {
        return;
    }
    let s = settings(8);
    let base = WavefrontOptions { pool_size: Some(PoolSize::Paths(700)), ..Default::default() };
    let waves = run_wavefront("rtiow-final", &s, base).film;
    for sync_every in [1, 24] {
        let wf = WavefrontOptions { sync_every, chunk_pools: 2, ..regenerating(base) };
        let r = run_wavefront("rtiow-final", &s, wf);
        assert_eq!(r.film, waves, "sync every {sync_every}");
    }
    // With the tail on a job of one pool, the share ends inside the first batch of 24: the rest
    // of that batch at least is speculative, and changes neither the film nor the counts.
    let s = settings(16);
    let wf =
        |k| WavefrontOptions { tail: Tail::Megakernel, sync_every: k, ..regenerating(Default::default()) };
    let (one, ahead) =
        (run_wavefront("three-spheres", &s, wf(1)), run_wavefront("three-spheres", &s, wf(24)));
    let (a, b) = (one.schedule.unwrap(), ahead.schedule.unwrap());
    eprintln!("batches of 1: {a:?}\nbatches of 24: {b:?}");
    assert!(b.speculative_iterations > 0 && b.speculative_dispatches > 0, "{b:?}");
    assert_eq!(ahead.film, one.film);
    assert_eq!(
        (b.iterations, b.idle_iterations, b.tail_passes, b.tail_paths),
        (a.iterations, 0, a.tail_passes, a.tail_paths)
    );
    assert_eq!((b.dispatches, b.empty_dispatches), (a.dispatches, a.empty_dispatches), "{a:?} vs {b:?}");
    // The queue counts too (the traffic model's items): the flushed paths still on the ray queue
    // past the end are counted by no speculative iteration.
    let items = |s: &wavetrace::gpu::wavefront::ScheduleStats| {
        s.state_traffic
            .as_ref()
            .unwrap()
            .passes
            .iter()
            .map(|p| (p.label.clone(), p.items))
            .collect::<Vec<_>>()
    };
    assert_eq!(items(&b), items(&a));
}

/// The path-state traffic model (issue 44) is charged with counts the render made: in waves the
/// intersect and shadow passes' items are every ray the film counts; regenerating, the camera
/// rays' hits and the paths going on from them are counted on the GPU (their queue entries are
/// marked) and equal the waves' histogram's bounce 0, since both trace the same camera rays, so
/// its figure is exact, not a bound. Where camera rays are stored (a ray sort), regenerating
/// renders have no such count and the model says its figure is a bound.
#[test]
fn path_state_traffic_is_charged_with_counted_items() {
    use wavetrace::gpu::wavefront::RaySort;
    if common::gpu().is_none() {
        return;
    }
    let cases = [
        ("rtiow-final", settings(8)),
        ("cornell", RenderSettings { nee: true, max_depth: 12, ..settings(8) }),
    ];
    for (scene, s) in cases {
        let waves = WavefrontOptions { pool_size: Some(PoolSize::Paths(700)), ..Default::default() };
        let w = run_wavefront(scene, &s, waves);
        let tail = WavefrontOptions { tail: Tail::Megakernel, ..regenerating(waves) };
        let r = run_wavefront(scene, &s, tail);
        let traffic = |o: &RenderOutput| o.schedule.as_ref().unwrap().state_traffic.clone().unwrap();
        let (wt, rt) = (traffic(&w), traffic(&r));
        let items = |t: &wavetrace::gpu::wavefront::traffic::StateTraffic, label: &str| {
            t.passes.iter().find(|p| p.label == label).map_or(0, |p| p.items)
        };
        assert_eq!(
            items(&wt, "intersect") + items(&wt, "shadow"),
            w.film.rays(),
            "{scene}: every ray traced"
        );
        assert!(s.nee == (items(&wt, "shadow") > 0), "{scene}: shadow rays where lights are sampled");
        let bounce0 = wt.first_bounce.expect("waves count bounce 0");
        assert!(bounce0[0] > 0 && bounce0[1] > 0, "{scene}: camera rays hit and go on");
        assert_eq!(rt.first_bounce, Some(bounce0), "{scene}: counted on the GPU as in the waves");
        assert!(wt.bytes_per_sample > 0.0 && rt.bytes_per_sample > 0.0);
        // A ray sort reads stored rays: camera rays are stored, and not counted apart.
        let sorted = WavefrontOptions { ray_sort: RaySort::Octant, ..regenerating(waves) };
        let st = traffic(&run_wavefront(scene, &s, sorted));
        assert_eq!(st.first_bounce, None, "{scene}: a bound without the counts");
        // No queues, no counts: no model.
        let off = WavefrontOptions { compaction: Compaction::Off, ..waves };
        assert!(run_wavefront(scene, &s, off).schedule.unwrap().state_traffic.is_none());
        // With per-pass timestamps each entry has its passes' time and its bytes over it; a frame
        // timed whole has neither.
        let timed = |timing| {
            let opts = MethodOptions { wavefront: waves, timing, ..Default::default() };
            traffic(&run(Method::Wavefront, scene, &s, &opts))
        };
        let framed = timed(Timing::Frame);
        assert!(framed.passes.iter().all(|p| p.seconds.is_none() && p.bytes_per_second.is_none()));
        let profiled = timed(Timing::Passes);
        let intersect = profiled.passes.iter().find(|p| p.label == "intersect").unwrap();
        let seconds = intersect.seconds.expect("intersect was timed");
        let bytes = (intersect.bytes_read + intersect.bytes_written) as f64;
        assert!(seconds > 0.0);
        assert_eq!(intersect.bytes_per_second, Some(bytes / seconds));
        assert_eq!(profiled.bytes_per_sample, framed.bytes_per_sample, "{scene}: the same counts");
    }
}
