//! SAH BVH build time over the final scene and over random sphere sets of growing size.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::Vec3;
use std::hint::black_box;
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

fn bvh_build(c: &mut Criterion) {
    let scene = wavetrace::scene::builtin::by_name("rtiow-final").unwrap();
    let boxes: Vec<Aabb> =
        scene.spheres.iter().map(|s| Aabb { min: s.center - s.radius, max: s.center + s.radius }).collect();
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
}

criterion_group!(benches, bvh_build);
criterion_main!(benches);
