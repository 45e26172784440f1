//! Russian roulette (`--roulette on`, pbrt-v4's rule; issue 46): the image does not change
//! beyond noise, paths get shorter, and every method ends the same paths, since the roulette's
//! random number comes from the shared counter-based generator. Small images: these run on the
//! software driver.

use crate::common;
use crate::lights::assert_same_image;

use wavetrace::film::Film;
use wavetrace::gpu::megakernel::MegakernelOptions;
use wavetrace::gpu::wavefront::{
    CompactStates, Compaction, QueueOrder, Schedule, ShadePasses, Tail, WavefrontOptions,
};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::options::PoolSize;
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(width: u32, height: u32, spp: u32, nee: bool) -> RenderSettings {
    RenderSettings { width, height, spp, max_depth: 50, seed: 1, accel: Accel::Bvh, nee, roulette: true }
}

fn run_with(method: Method, scene: &str, s: &RenderSettings, opts: &MethodOptions) -> Film {
    let scene = builtin::by_name(scene).unwrap();
    let gpu = if method.needs_gpu() { common::gpu() } else { None };
    render(method, &scene, s, opts, gpu, &|_| {}).unwrap().film
}

fn run(method: Method, scene: &str, s: &RenderSettings) -> Film {
    run_with(method, scene, s, &MethodOptions::default())
}

/// Rays per sample: camera, bounce and shadow rays over every sample of the film.
fn rays_per_sample(f: &Film) -> f64 {
    f.rays() as f64 / (f.spp as f64 * f.pixels.len() as f64)
}

/// Roulette is unbiased: with it on, the CPU renders the image it renders without, within noise
/// (independent renders: another seed), and traces shorter paths to get there.
#[test]
fn roulette_keeps_the_cpu_image_and_shortens_its_paths() {
    for (scene, s, shortest) in [
        // Cornell's white walls (0.73) end about a quarter of the paths at every bounce.
        ("cornell", settings(16, 16, 1024, true), 0.6),
        // The book's final scene: most paths escape to the sky within a few bounces anyway.
        ("rtiow-final", settings(48, 27, 64, false), 0.95),
    ] {
        let on = run(Method::Cpu, scene, &s);
        let off = run(Method::Cpu, scene, &RenderSettings { roulette: false, seed: 7, ..s.clone() });
        assert_same_image(&format!("{scene} roulette on vs off"), &on, &off);
        let (r_on, r_off) = (rays_per_sample(&on), rays_per_sample(&off));
        eprintln!("{scene}: {r_on:.3} rays per sample with roulette, {r_off:.3} without");
        assert!(
            r_on < shortest * r_off,
            "{scene}: roulette should shorten paths ({r_on} vs {r_off} rays per sample)"
        );
        assert!(r_on >= 1.0, "{scene}: at least the camera ray");
    }
}

/// f64 ends the same paths as f32, up to the rare throughput that rounding puts on the other
/// side of the roulette's draw: the ground truth can run with roulette on too.
#[test]
fn roulette_agrees_between_f32_and_f64() {
    let s = settings(48, 27, 32, false);
    common::assert_agree_rays(
        "rtiow-final roulette f32 vs f64",
        &run(Method::Cpu, "rtiow-final", &s),
        &run(Method::CpuF64, "rtiow-final", &s),
        1e-2,
    );
}

/// Every GPU method ends the paths the CPU ends: per-pixel z-tests on the same paths and equal
/// ray counts (up to rounding, `common::F32_RAY_TOLERANCE`), with next-event estimation (the
/// wavefront traces the shadow ray of a path the roulette ends in its shade pass) and without.
#[test]
fn every_gpu_method_ends_the_cpus_paths() {
    if common::gpu().is_none() {
        return;
    }
    let regenerate = MethodOptions {
        megakernel: MegakernelOptions { schedule: Schedule::Regenerate, ..Default::default() },
        ..Default::default()
    };
    let wavefront_regenerate = MethodOptions {
        wavefront: WavefrontOptions {
            schedule: Schedule::Regenerate,
            tail: Tail::Megakernel,
            ..Default::default()
        },
        ..Default::default()
    };
    for (scene, s) in [("cornell", settings(32, 32, 32, true)), ("rtiow-final", settings(48, 27, 16, false))]
    {
        let cpu = run(Method::Cpu, scene, &s);
        for (label, method, opts) in [
            ("megakernel", Method::Megakernel, MethodOptions::default()),
            ("megakernel regenerate", Method::Megakernel, regenerate.clone()),
            ("wavefront", Method::Wavefront, MethodOptions::default()),
            ("wavefront regenerate tail", Method::Wavefront, wavefront_regenerate.clone()),
        ] {
            let gpu = run_with(method, scene, &s, &opts);
            common::assert_agree_rays(
                &format!("{scene} roulette cpu vs {label}"),
                &cpu,
                &gpu,
                common::F32_RAY_TOLERANCE,
            );
        }
    }
}

/// The wavefront ends paths by roulette in its shade pass, the megakernel in its bounce loop:
/// sample for sample the same image, for every way the wavefront keeps its queues (the ended
/// path's shadow ray is traced in shade, so no queue carries it); and regenerating, the waved
/// film bit for bit (the megakernel tail: the same paths, up to rounding).
#[test]
fn the_wavefront_ends_the_megakernels_paths_for_every_knob() {
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings { max_depth: 12, ..settings(40, 24, 8, true) };
    let megakernel = run(Method::Megakernel, "cornell", &s);
    let wavefront = |wf: WavefrontOptions| {
        run_with(Method::Wavefront, "cornell", &s, &MethodOptions { wavefront: wf, ..Default::default() })
    };
    // Each compaction method once, the shade passes in turn (each run compiles its own
    // pipelines: most of this test's cost with a cold shader cache).
    let mut knobs = Vec::new();
    for (compaction, shade) in [
        (Compaction::Off, ShadePasses::PerMaterial),
        (Compaction::Atomic, ShadePasses::Single),
        (Compaction::Scan, ShadePasses::PerMaterial),
    ] {
        knobs.push(WavefrontOptions {
            pool_size: Some(PoolSize::Paths(700)),
            compaction,
            shade,
            ..Default::default()
        });
    }
    knobs.push(WavefrontOptions {
        pool_size: Some(PoolSize::Paths(700)),
        queue_order: QueueOrder::Slot,
        ..Default::default()
    });
    for waves in knobs {
        let film = wavefront(waves);
        let (frac, mean_diff) = common::same_sample_agreement(&film, &megakernel, 1e-6);
        assert!(frac >= 0.995 && mean_diff <= 1e-3, "{waves:?}: {frac} of pixels match, means {mean_diff}");
        assert!((film.rays() as f64 - megakernel.rays() as f64).abs() <= 1e-3 * megakernel.rays() as f64);
        if waves.compaction == Compaction::Off {
            continue; // regenerating needs queues
        }
        let regen = WavefrontOptions { schedule: Schedule::Regenerate, sync_every: 3, ..waves };
        assert_eq!(wavefront(regen), film, "{regen:?}");
        let compacted = WavefrontOptions { compact_states: CompactStates::On, ..regen };
        assert_eq!(wavefront(compacted), film, "{compacted:?}");
        let tail = WavefrontOptions { tail: Tail::Megakernel, ..regen };
        common::assert_same_paths(&format!("{tail:?}"), &wavefront(tail), &film);
    }
}
