//! SAH BVH build time over the final scene, over random sphere sets of growing size, and over
//! the million spheres of `spheres-1000000` (the scale experiment's largest scene).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;
use wavetrace::bvh::{Aabb, Bvh};
use wavetrace::rng::Stream;

fn random_boxes(n: usize) -> Vec<Aabb> {
    let mut s = Stream::new(1);
    (0..n)
        .map(|_| {
            let c = Vec3::new(s.range(-100.0, 100.0), s.range(-100.0, 100.0), s.range(-100.0, 100.0));
            let r = s.range(0.05, 0.5);
            Aabb { min: c - r, max: c + r }
        })
        .collect()
}

fn scene_boxes(name: &str) -> Vec<Aabb> {
    let scene = wavetrace::scene::builtin::by_name(name).unwrap();
    scene.spheres.iter().map(|s| Aabb { min: s.center - s.radius, max: s.center + s.radius }).collect()
}

fn bvh_build(c: &mut Criterion) {
    let boxes = scene_boxes("rtiow-final");
    c.bench_function("bvh_build/rtiow-final", |b| b.iter(|| Bvh::build(black_box(&boxes))));
    let mut group = c.benchmark_group("bvh_build/random");
    group.sample_size(10);
    for n in [1_000, 10_000, 100_000] {
        let boxes = random_boxes(n);
        group.bench_with_input(BenchmarkId::from_parameter(n), &boxes, |b, boxes| {
            b.iter(|| Bvh::build(boxes))
        });
    }
    group.finish();
    // About a second per build (2 cores): criterion's fewest samples and a measuring time that
    // fits them keep this case to about 20 s.
    let mut group = c.benchmark_group("bvh_build");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(15));
    let boxes = scene_boxes("spheres-1000000");
    group.bench_function("spheres-1000000", |b| b.iter(|| Bvh::build(black_box(&boxes))));
    group.finish();
}

criterion_group!(benches, bvh_build);
criterion_main!(benches);
