//! CPU reference throughput on a small image (f32 and f64), in path samples per second.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::settings::{Accel, RenderSettings};

fn cpu_reference(c: &mut Criterion) {
    let settings = RenderSettings {
        width: 160,
        height: 90,
        spp: 8,
        max_depth: 50,
        seed: 0,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    };
    let mut group = c.benchmark_group("cpu_reference");
    group.sample_size(10);
    group.throughput(Throughput::Elements(settings.sample_count()));
    for scene_name in ["three-spheres", "rtiow-final"] {
        let scene = wavetrace::scene::builtin::by_name(scene_name).unwrap();
        for method in [Method::Cpu, Method::CpuF64] {
            group.bench_function(format!("{scene_name}/{}", method.name()), |b| {
                b.iter(|| {
                    render(method, &scene, &settings, &MethodOptions::default(), None, &|_| {}).unwrap()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, cpu_reference);
criterion_main!(benches);
