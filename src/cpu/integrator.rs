//! One path from camera to light: the book's `ray_color` as a loop; twin of the megakernel's
//! `trace_path` in `shaders/megakernel.wgsl`.

use super::{background::background, bvh::closest_hit, camera::Camera, material::scatter};
use super::{ray::Ray, ray::T_MIN, real::Real, sphere::outward_normal, vec3::V3};
use crate::layout::material_kind;
use crate::packed_scene::PackedScene;
use crate::rng::{uniform4, Purpose};
use crate::settings::RenderSettings;

/// What one path brought back.
#[derive(Clone, Copy, Debug)]
pub struct PathSample<T> {
    pub radiance: V3<T>,
    /// Rays traced (closest-hit queries), camera ray included.
    pub rays: u32,
}

/// Radiance carried by sample `sample` of pixel (x, y), and the rays it took.
pub fn trace_path<T: Real>(
    scene: &PackedScene,
    camera: &Camera<T>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    sample: u32,
) -> PathSample<T> {
    let (seed, max_depth) = (settings.seed, settings.max_depth);
    let pixel = y * settings.width + x;
    let mut ray = camera.ray(x, y, uniform4(pixel, sample, 0, Purpose::Camera, seed));
    // Every path ends at one light (an emitter or the background), so radiance is the
    // throughput at that point times its emission.
    let mut throughput = V3::splat(T::one());
    for bounce in 0..max_depth {
        let rays = bounce + 1;
        let Some(hit) = closest_hit(&scene.nodes, &scene.spheres, &ray, T::of(T_MIN)) else {
            return PathSample {
                radiance: throughput.mul_elem(background(&scene.background, ray.dir)),
                rays,
            };
        };
        let sphere = &scene.spheres[hit.sphere as usize];
        let material = &scene.materials[scene.sphere_material[hit.sphere as usize] as usize];
        if material.kind == material_kind::EMISSIVE {
            return PathSample { radiance: throughput.mul_elem(V3::of(material.color)), rays };
        }
        let p = ray.at(hit.t);
        let outward = outward_normal(sphere, p);
        let front_face = ray.dir.dot(outward) < T::zero();
        let normal = if front_face { outward } else { -outward };
        let u = uniform4(pixel, sample, bounce, Purpose::Scatter, seed);
        let Some(s) = scatter(material, &ray, p, normal, front_face, u) else {
            return PathSample { radiance: V3::splat(T::zero()), rays };
        };
        throughput = throughput.mul_elem(s.attenuation);
        ray = Ray { origin: p, dir: s.dir };
    }
    // Out of depth: as in the book, the unfinished path contributes nothing.
    PathSample { radiance: V3::splat(T::zero()), rays: max_depth }
}
