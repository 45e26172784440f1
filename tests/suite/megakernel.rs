//! The megakernel's two schedules: one path per thread (`waves`, the seeds' form) and
//! persistent threads that regenerate paths (`regenerate`). Regeneration changes which thread
//! traces which sample and when, never a sample's random numbers nor the order the film adds a
//! pixel's samples, so both give the same film; and each render reports the GPU memory it took.

use crate::common;

use glam::Vec3;
use wavetrace::gpu::megakernel::MegakernelOptions;
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::options::PoolSize;
use wavetrace::options::Schedule;
use wavetrace::scene::{builtin, Mesh, MeshSource, Scene};
use wavetrace::settings::{Accel, RenderSettings};

fn settings(width: u32, height: u32, spp: u32, nee: bool) -> RenderSettings {
    RenderSettings { width, height, spp, max_depth: 16, seed: 3, accel: Accel::Bvh, nee, roulette: false }
}

fn run(method: Method, scene: &Scene, s: &RenderSettings, mk: MegakernelOptions) -> RenderOutput {
    let opts = MethodOptions { megakernel: mk, ..Default::default() };
    render(method, scene, s, &opts, common::gpu(), &|_| {}).unwrap()
}

fn regenerate(threads: Option<u32>) -> MegakernelOptions {
    MegakernelOptions { schedule: Schedule::Regenerate, threads, ..Default::default() }
}

/// `cornell` (quads, an emitting quad) with a triangle prism standing on its floor: every
/// primitive kind, and lights for next-event estimation.
fn every_kind() -> Scene {
    let mut scene = builtin::by_name("cornell").unwrap();
    let (a, b, c) =
        (Vec3::new(150.0, 0.1, 300.0), Vec3::new(300.0, 0.1, 300.0), Vec3::new(225.0, 250.0, 350.0));
    scene.meshes.push(Mesh {
        source: MeshSource::File("inline.obj".into()),
        triangles: vec![[a, b, c]],
        uvs: None,
        material: 0,
    });
    scene.spheres.push(wavetrace::scene::Sphere {
        center: Vec3::new(400.0, 90.0, 200.0),
        radius: 90.0,
        material: 0,
    });
    scene
}

fn cases() -> Vec<(Scene, RenderSettings)> {
    let final_scene = builtin::by_name("rtiow-final").unwrap();
    vec![
        (final_scene, settings(24, 16, 8, false)),
        (every_kind(), settings(16, 16, 8, false)),
        (every_kind(), settings(16, 16, 8, true)),
    ]
}

/// The claim, on this driver bit for bit: the regenerating megakernel's film is the
/// naive one's, with and without next-event estimation, on spheres, quads and triangles, for
/// the default threads, for fewer threads than samples (each takes many paths) and for a thread
/// count that is not a whole number of workgroups; and over several dispatches.
#[test]
fn regenerate_gives_the_naive_film_bit_for_bit() {
    if common::gpu().is_none() {
        return;
    }
    for (scene, s) in cases() {
        let naive = run(Method::Megakernel, &scene, &s, MegakernelOptions::default());
        for threads in [None, Some(64), Some(100)] {
            for samples_per_dispatch in [1 << 21, 1000] {
                let mk = MegakernelOptions { samples_per_dispatch, ..regenerate(threads) };
                let r = run(Method::Megakernel, &scene, &s, mk);
                assert_eq!(naive.film, r.film, "{} nee={} {mk:?}", scene.name, s.nee);
            }
        }
    }
}

/// Every sample is taken exactly once, however the lanes of a subgroup run out of work: with
/// subgroups, samples are handed out one atomic per subgroup inside a loop that lanes leave
/// together (megakernel_regenerate.wgsl), and a lane whose share of paths is taken idles while the
/// others go on. A lost sample leaves its slot of the sample buffer unwritten (the film differs);
/// a repeated one makes the finished count differ from the samples asked for, which the host
/// refuses (`check_finished`, and per dispatch where the driver caps loops). Per-thread shares
/// of 1 and 3 make lanes stop at different times and launches repeat.
#[test]
fn regenerate_takes_every_sample_once() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(24, 16, 4, false);
    let naive = run(Method::Megakernel, &scene, &s, MegakernelOptions::default());
    for threads in [1, 13, 64, 200] {
        for paths_per_thread in [1, 3, 1000] {
            let mk =
                MegakernelOptions { paths_per_thread: Some(paths_per_thread), ..regenerate(Some(threads)) };
            let r = run(Method::Megakernel, &scene, &s, mk);
            assert_eq!(naive.film, r.film, "{mk:?}");
        }
    }
}

/// Against the CPU reference (the ground truth), by the per-pixel z-test of DESIGN.md §4.
#[test]
fn regenerate_agrees_with_the_cpu_reference() {
    if common::gpu().is_none() {
        return;
    }
    for (scene, s) in cases() {
        let s = RenderSettings { spp: 32, ..s };
        let cpu = run(Method::Cpu, &scene, &s, MegakernelOptions::default());
        let r = run(Method::Megakernel, &scene, &s, regenerate(Some(256)));
        common::assert_agree_rays(
            &format!("{} nee={}", scene.name, s.nee),
            &cpu.film,
            &r.film,
            common::F32_RAY_TOLERANCE,
        );
    }
}

#[test]
fn regenerate_repeats_bit_identically() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(32, 18, 4, false);
    let a = run(Method::Megakernel, &scene, &s, regenerate(Some(96)));
    let b = run(Method::Megakernel, &scene, &s, regenerate(Some(96)));
    assert_eq!(a.film, b.film);
}

/// What the schedule is for: lanes stop idling while their subgroup's longest path finishes.
/// Counted with `--instrument` at the top of every bounce, on the scene the seeds measured.
#[test]
fn regenerate_keeps_more_lanes_busy() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    if !ctx.summary.subgroups {
        common::skipped(
            "megakernel::regenerate_keeps_more_lanes_busy",
            "the adapter has no subgroup operations",
        );
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = RenderSettings { max_depth: 50, ..settings(64, 36, 8, false) };
    let efficiency = |mk: MegakernelOptions| {
        let opts = MethodOptions { megakernel: mk, instrument: true, ..Default::default() };
        let out = render(Method::Megakernel, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
        out.simd.unwrap()["megakernel_bounce"].efficiency
    };
    let naive = efficiency(MegakernelOptions::default());
    let regen = efficiency(regenerate(Some(256)));
    eprintln!("bounce SIMD efficiency: naive {naive:.3}, regenerating {regen:.3}");
    assert!(regen > naive + 0.1, "regenerating {regen:.3} vs naive {naive:.3}");
}

#[test]
fn bad_thread_counts_are_refused() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(8, 8, 1, false);
    let too_many = ctx.summary.max_compute_workgroups_per_dimension as u64 * 64 + 1;
    let cases = [
        (regenerate(Some(0)), "at least 1"),
        (regenerate(Some(u32::try_from(too_many).unwrap_or(u32::MAX))), "can launch"),
        (MegakernelOptions { threads: Some(64), ..Default::default() }, "--schedule regenerate"),
    ];
    for (mk, expected) in cases {
        let opts = MethodOptions { megakernel: mk, ..Default::default() };
        let err = render(Method::Megakernel, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap_err();
        let msg = format!("{err:#}");
        assert!(msg.contains(expected), "{mk:?}: {msg}");
    }
}

/// Every GPU render accounts for its memory by category; the categories add up to the total,
/// and the figures follow from the job: the film holds 64 bytes a pixel, the naive megakernel's
/// sample buffer 16 bytes a sample of its largest dispatch.
#[test]
fn memory_is_accounted_by_category() {
    if common::gpu().is_none() {
        return;
    }
    let scene = every_kind();
    let s = settings(20, 10, 4, true);
    let naive = run(Method::Megakernel, &scene, &s, MegakernelOptions::default());
    let regen = run(Method::Megakernel, &scene, &s, regenerate(Some(64)));
    let wave =
        render(Method::Wavefront, &scene, &s, &MethodOptions::default(), common::gpu(), &|_| {}).unwrap();
    let cpu = run(Method::Cpu, &scene, &s, MegakernelOptions::default());
    assert!(cpu.memory.is_none());
    for (name, out) in [("naive", &naive), ("regenerate", &regen), ("wavefront", &wave)] {
        let m = out.memory.as_ref().unwrap();
        assert_eq!(m.total, m.by_category.values().sum::<u64>(), "{name}: {m:?}");
        assert!(m.peak >= m.total + m.by_category["film"], "{name}: the film's read-back copy");
        assert_eq!(m.by_category["film"], 20 * 10 * 64, "{name}");
        assert!(m.by_category["scene"] > 0, "{name}");
    }
    let (n, r, w) = (naive.memory.unwrap(), regen.memory.unwrap(), wave.memory.unwrap());
    assert_eq!(n.by_category["samples"], 20 * 10 * 4 * 16);
    // Every GPU method holds the failure counters (self-hits, depth cuts); the naive megakernel
    // nothing else of the kind.
    let failures = wavetrace::gpu::scene_buffers::FAILURE_BYTES;
    assert_eq!(n.by_category["counters"], failures, "the naive megakernel's counters");
    assert!(r.by_category["counters"] > failures, "the regenerating megakernel's work counters");
    for key in ["path_state", "queues", "shadow_queue", "counters"] {
        assert!(w.by_category[key] > 0, "wavefront {key}: {w:?}");
    }
    for key in ["path_state", "queues", "shadow_queue"] {
        assert!(!n.by_category.contains_key(key), "megakernel {key}");
    }
    // A bigger pool holds more path state.
    let opts = |pool| MethodOptions {
        wavefront: wavetrace::gpu::wavefront::WavefrontOptions {
            pool_size: Some(PoolSize::Paths(pool)),
            ..Default::default()
        },
        ..Default::default()
    };
    let small = render(Method::Wavefront, &scene, &s, &opts(64), common::gpu(), &|_| {}).unwrap();
    let big = render(Method::Wavefront, &scene, &s, &opts(512), common::gpu(), &|_| {}).unwrap();
    let state = |o: &RenderOutput| o.memory.as_ref().unwrap().by_category["path_state"];
    assert!(state(&big) > 7 * state(&small), "{} vs {}", state(&big), state(&small));
}

/// Where the driver caps loops (llvmpipe), a dispatch whose persistent threads it cut short is
/// traced again with fewer paths per thread, and the film is still the naive one's. Forced
/// here by starting far above any safe number of paths per thread.
#[test]
fn a_dispatch_the_loop_cap_cuts_is_traced_again() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    if !ctx.summary.name.contains("llvmpipe") {
        // No loop cap on this driver, so nothing to cut: the retry path is not exercised here.
        common::skipped(
            "megakernel::a_dispatch_the_loop_cap_cuts_is_traced_again",
            "only llvmpipe caps loops",
        );
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = RenderSettings { max_depth: 50, ..settings(64, 36, 4, false) };
    let naive = run(Method::Megakernel, &scene, &s, MegakernelOptions::default());
    let mk = MegakernelOptions { paths_per_thread: Some(100_000), ..regenerate(Some(64)) };
    let r = run(Method::Megakernel, &scene, &s, mk);
    assert_eq!(naive.film, r.film);
    // One trace launch and one accumulate pass if nothing had been cut.
    assert!(r.dispatches > 2, "{} passes: the dispatch was not traced again", r.dispatches);
}

/// Without `--threads`, a discrete GPU gets 2^18 persistent threads (97% of an H100's 132 SMs ×
/// 2048), other adapters the count that was fastest on llvmpipe.
#[test]
fn the_default_threads_follow_the_adapter() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    use wavetrace::gpu::megakernel::persistent_threads;
    let threads = persistent_threads(ctx, None, 64).unwrap();
    let expected = if ctx.summary.device_type == "DiscreteGpu" { 1 << 18 } else { 1 << 16 };
    assert_eq!(threads, expected, "{}", ctx.summary.device_type);
    // An explicit count wins, rounded up to whole workgroups.
    assert_eq!(persistent_threads(ctx, Some(100), 64).unwrap(), 128);
}
