//! The wavefront against the megakernel: every knob combination traces the same paths (shared
//! RNG), so images match to rounding; repeat renders are bit-identical; measurements are there.

use crate::common;

use wavetrace::film::Film;
use wavetrace::gpu::wavefront::{Compaction, ShadePasses, WavefrontOptions};
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(spp: u32) -> RenderSettings {
    RenderSettings { width: 40, height: 24, spp, max_depth: 50, seed: 3, accel: Accel::Bvh, nee: false }
}

fn run(method: Method, scene: &str, s: &RenderSettings, opts: &MethodOptions) -> RenderOutput {
    let scene = builtin::by_name(scene).unwrap();
    render(method, &scene, s, opts, common::gpu(), &|_| {}).unwrap()
}

fn all_knobs() -> Vec<WavefrontOptions> {
    let mut v = Vec::new();
    for compaction in [Compaction::Off, Compaction::Atomic, Compaction::Scan] {
        for shade in [ShadePasses::PerMaterial, ShadePasses::Single] {
            // A small pool so every render runs several waves.
            v.push(WavefrontOptions { pool_size: Some(7000), workgroup_size: 64, compaction, shade });
        }
    }
    v.push(WavefrontOptions { pool_size: None, workgroup_size: 32, ..Default::default() });
    v
}

/// The bar: ≥ 99.5% of pixels within 1e-3 relative (per channel), means within 0.1%.
fn assert_match(what: &str, a: &Film, b: &Film) {
    let close = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| {
            let (m, n) = (p.mean(), q.mean());
            (0..3).all(|c| (m[c] - n[c]).abs() <= 1e-3 * m[c].abs().max(n[c].abs()).max(1e-6))
        })
        .count();
    let frac = close as f64 / a.pixels.len() as f64;
    let mean_diff = (a.image_mean() - b.image_mean()).abs() / b.image_mean();
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
        wavefront: WavefrontOptions { pool_size: Some(3000), ..Default::default() },
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
    let opts = MethodOptions { instrument: true, ..Default::default() };
    let out = run(Method::Wavefront, "rtiow-final", &s, &opts);
    let t = out.timings.as_ref().unwrap();
    for label in ["generate", "queue_setup_intersect", "intersect", "queue_setup_shade", "accumulate"] {
        assert!(t.passes.contains_key(label), "pass {label} timed");
    }
    for kind in ["shade_lambertian", "shade_metal", "shade_dielectric"] {
        assert_eq!(t.passes[kind].passes, 50, "{kind} once per bounce");
        assert_eq!(t.per_bounce[kind].len(), 50);
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
        let mk = run(Method::Megakernel, "rtiow-final", &s, &opts);
        let mk_simd = mk.simd.unwrap();
        // Inside the megakernel's material branches lanes diverge; the wavefront's per-material
        // passes run converged.
        assert!(mk_simd["megakernel_lambertian"].efficiency < simd["shade_lambertian"].efficiency);
    }
}

#[test]
fn an_oversized_pool_is_reduced_not_fatal() {
    if common::gpu().is_none() {
        return;
    }
    let opts = MethodOptions {
        wavefront: WavefrontOptions { pool_size: Some(u32::MAX), ..Default::default() },
        ..Default::default()
    };
    let out = run(Method::Wavefront, "furnace", &settings(1), &opts);
    assert!(out.pool.unwrap() < u32::MAX);
}
