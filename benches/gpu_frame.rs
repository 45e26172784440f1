//! A megakernel frame and a wavefront frame (each knob setting) on a small scene, timed by GPU
//! time (the sum of the passes' timestamp intervals, via criterion's `iter_custom`), so
//! `cargo bench --features bench --bench gpu_frame` compares the methods on this machine's adapter. Set
//! `WAVETRACE_BENCH_SCENE` to bench another built-in scene and `WAVETRACE_BENCH_NEE=on` for
//! next-event estimation (e.g. `WAVETRACE_BENCH_SCENE=cornell WAVETRACE_BENCH_NEE=on`).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;
use wavetrace::gpu::wavefront::{Compaction, ShadePasses, WavefrontOptions};
use wavetrace::gpu::GpuContext;
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::settings::{Accel, RenderSettings};

fn gpu_frame(c: &mut Criterion) {
    let ctx = match GpuContext::new(std::env::var("WAVETRACE_ADAPTER").ok().as_deref()) {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("gpu_frame: no GPU adapter, nothing to bench: {e}");
            return;
        }
    };
    let scene_name = std::env::var("WAVETRACE_BENCH_SCENE").unwrap_or_else(|_| "three-spheres".into());
    let scene = wavetrace::scene::builtin::by_name(&scene_name).expect("a built-in scene");
    let settings = RenderSettings {
        width: 160,
        height: 90,
        spp: 4,
        max_depth: 50,
        seed: 0,
        accel: Accel::Bvh,
        nee: std::env::var("WAVETRACE_BENCH_NEE").is_ok_and(|v| v == "on"),
        roulette: false,
    };
    let nee = if settings.nee { "-nee" } else { "" };
    let mut group = c.benchmark_group(format!("gpu_frame/{scene_name}{nee}"));
    group.sample_size(10);
    group.throughput(Throughput::Elements(settings.sample_count()));

    let mut variants = vec![("megakernel".to_string(), Method::Megakernel, MethodOptions::default())];
    for (name, compaction, shade) in [
        ("atomic", Compaction::Atomic, ShadePasses::PerMaterial),
        ("scan", Compaction::Scan, ShadePasses::PerMaterial),
        ("off", Compaction::Off, ShadePasses::PerMaterial),
        ("atomic-single-shade", Compaction::Atomic, ShadePasses::Single),
    ] {
        let wavefront = WavefrontOptions { compaction, shade, ..Default::default() };
        variants.push((
            format!("wavefront-{name}"),
            Method::Wavefront,
            MethodOptions { wavefront, ..Default::default() },
        ));
    }
    for (name, method, opts) in &variants {
        group.bench_function(name.as_str(), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let out = render(*method, &scene, &settings, opts, Some(&ctx), &|_| {}).expect("render");
                    let seconds = out.timings.expect("GPU timings").total_seconds();
                    total += Duration::from_secs_f64(seconds);
                }
                total
            })
        });
    }
    group.finish();
}

criterion_group!(benches, gpu_frame);
criterion_main!(benches);
