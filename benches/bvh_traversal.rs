//! CPU traversal alone, per layout (issue 59): closest hits of the rays a path tracer asks for
//! (the camera's rays through a 160×90 frame and, from each hit, one bounce in a random
//! direction on the hit's side), on the 10⁶-triangle terrain and mesh-room. The render's other
//! work (shading, sampling, textures) is left out, so the ratio of layouts here bounds what a
//! layout can gain in a whole CPU render.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use wavetrace::bvh::collapse::Collapse;
use wavetrace::bvh::BvhLayout;
use wavetrace::cpu::bvh::closest_hit;
use wavetrace::cpu::primitive::outward_normal;
use wavetrace::cpu::ray::Ray;
use wavetrace::method::{prepare, Method, MethodOptions};
use wavetrace::numerics::SphereHit;
use wavetrace::settings::{Accel, RenderSettings};
use wavetrace::vec3::V3;

fn bvh_traversal(c: &mut Criterion) {
    let settings = RenderSettings {
        width: 160,
        height: 90,
        spp: 1,
        max_depth: 50,
        seed: 0,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    };
    let mut group = c.benchmark_group("bvh_traversal");
    group.sample_size(10);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/");
    for name in ["triangles-1000000", "scenes/mesh-room.json"] {
        let arg = if name.ends_with(".json") { format!("{dir}{name}") } else { name.to_string() };
        let scene = wavetrace::scene::Scene::resolve(&arg).unwrap();
        let mut rays = None;
        for layout in [BvhLayout::Binary, BvhLayout::Wide] {
            let options = MethodOptions { bvh: layout, collapse: Collapse::default(), ..Default::default() };
            let (packed, frame) = prepare(Method::Cpu, &scene, &settings, &options).unwrap();
            let t_min = packed.numerics.ray_offset.t_min();
            let rays = rays.get_or_insert_with(|| path_rays(&packed, &frame, &settings, t_min));
            group.throughput(Throughput::Elements(rays.len() as u64));
            let short = name.trim_start_matches("scenes/").trim_end_matches(".json");
            group.bench_function(format!("{short}/{}", layout.name()), |b| {
                b.iter(|| {
                    let (nodes, prims) = (packed.bvh_nodes(), &packed.primitives);
                    rays.iter()
                        .filter(|r| closest_hit(nodes, prims, r, t_min, SphereHit::Stable, &mut ()).is_some())
                        .count()
                })
            });
        }
    }
    group.finish();
}

/// Camera rays, and from each hit one bounce into the hit's side.
fn path_rays(
    packed: &wavetrace::packed_scene::PackedScene,
    frame: &wavetrace::camera::CameraFrame,
    settings: &RenderSettings,
    t_min: f32,
) -> Vec<Ray<f32>> {
    let camera = wavetrace::cpu::camera::Camera::<f32>::new(frame);
    let mut s = wavetrace::rng::Stream::new(7);
    let mut rays = Vec::new();
    for y in 0..settings.height {
        for x in 0..settings.width {
            let ray = camera.ray(x, y, [0.5, 0.5, 0.5, 0.5]);
            rays.push(ray);
            let nodes = packed.bvh_nodes();
            if let Some(h) = closest_hit(nodes, &packed.primitives, &ray, t_min, SphereHit::Stable, &mut ()) {
                let n = outward_normal(&packed.primitives[h.prim as usize], ray.at(h.t));
                let n = if n.dot(ray.dir) > 0.0 { n * -1.0 } else { n };
                let r = V3::new(s.range(-1.0, 1.0), s.range(-1.0, 1.0), s.range(-1.0, 1.0));
                let d = (n + r.normalize()).normalize();
                rays.push(Ray { origin: ray.at(h.t), dir: d });
            }
        }
    }
    rays
}

criterion_group!(benches, bvh_traversal);
criterion_main!(benches);
