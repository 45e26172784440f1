//! One path from camera to light: the book's `ray_color` as a loop; twin of the megakernel's
//! `trace_path` in `shaders/megakernel.wgsl`.

use super::bvh::{closest_hit, occluded};
use super::light::{diffuse_pdf, emission_weight, next_event};
use super::{background::background, camera::Camera, material::scatter};
use super::{primitive::outward_normal, ray::Ray, ray::T_MIN, real::Real, vec3::V3};
use crate::layout::material_kind;
use crate::packed_scene::PackedScene;
use crate::rng::{uniform4, Purpose};
use crate::settings::RenderSettings;

/// What one path brought back.
#[derive(Clone, Copy, Debug)]
pub struct PathSample<T> {
    pub radiance: V3<T>,
    /// Rays traced (closest-hit and shadow queries), camera ray included.
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
    let mut throughput = V3::splat(T::one());
    let mut radiance = V3::splat(T::zero());
    let mut rays = 0;
    // When the previous hit sampled the lights: the density of this ray's direction under the
    // diffuse bounce, for the MIS weight of the emission it may find.
    let mut bsdf_pdf: Option<T> = None;
    let nee = settings.nee && !scene.lights.is_empty();
    for bounce in 0..max_depth {
        rays += 1;
        let Some(hit) = closest_hit(&scene.nodes, &scene.primitives, &ray, T::of(T_MIN)) else {
            radiance = radiance + throughput.mul_elem(background(&scene.background, ray.dir));
            return PathSample { radiance, rays };
        };
        let prim = &scene.primitives[hit.prim as usize];
        let material = &scene.materials[prim.material as usize];
        let p = ray.at(hit.t);
        if material.kind == material_kind::EMISSIVE {
            let w = bsdf_pdf
                .map_or(T::one(), |pdf| emission_weight(scene, hit.prim, ray.origin, p, ray.dir, hit.t, pdf));
            radiance = radiance + throughput.mul_elem(V3::of(material.color)) * w;
            return PathSample { radiance, rays };
        }
        let outward = outward_normal(prim, p);
        let front_face = ray.dir.dot(outward) < T::zero();
        let normal = if front_face { outward } else { -outward };
        let u = uniform4(pixel, sample, bounce, Purpose::Scatter, seed);
        let Some(s) = scatter(material, &ray, p, normal, front_face, u) else {
            return PathSample { radiance, rays };
        };
        // Direct light at diffuse hits, when the ray it stands in for (ray bounce + 2) is within
        // the depth limit.
        let lights_sampled = nee && material.kind == material_kind::LAMBERTIAN && bounce + 2 <= max_depth;
        // (A zero density, a bounce exactly along the surface, counts as no light sampling, as
        // on the GPU.)
        bsdf_pdf = lights_sampled.then(|| diffuse_pdf(normal.dot(s.dir))).filter(|&p| p > T::zero());
        if lights_sampled {
            let u = uniform4(pixel, sample, bounce, Purpose::Light, seed);
            if let Some(shadow) = next_event(scene, p, normal, u) {
                rays += 1;
                let t_min = T::of(T_MIN);
                if !occluded(&scene.nodes, &scene.primitives, &shadow.ray, t_min, shadow.t_max, shadow.light)
                {
                    radiance = radiance + throughput.mul_elem(s.attenuation).mul_elem(shadow.weight);
                }
            }
        }
        throughput = throughput.mul_elem(s.attenuation);
        ray = Ray { origin: p, dir: s.dir };
    }
    // Out of depth: as in the book, the unfinished path adds nothing more.
    PathSample { radiance, rays }
}
