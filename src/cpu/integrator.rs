//! One path from camera to light: the book's `ray_color` as a loop; twin of the megakernel's
//! `trace_path` in `shaders/megakernel.wgsl`.

use super::bvh::{closest_hit_observed, occluder_observed};
use super::light::{diffuse_pdf, emission_weight, next_event};
use super::observe::PathObserver;
use super::offset::{is_self_hit, spawn_origin, surface_point, NO_ORIGIN};
use super::{background::background, camera::Camera, material::scatter};
use super::{primitive::outward_normal, ray::Ray, real::Real, vec3::V3};
use crate::layout::material_kind;
use crate::numerics::Failures;
use crate::packed_scene::PackedScene;
use crate::rng::{uniform4, Purpose};
use crate::settings::RenderSettings;

/// What one path brought back.
#[derive(Clone, Copy, Debug)]
pub struct PathSample<T> {
    pub radiance: V3<T>,
    /// Rays traced (closest-hit and shadow queries), camera ray included.
    pub rays: u32,
    /// Its self-hits (`offset::is_self_hit`) and whether it was cut at `max_depth` (0 or 1).
    pub failures: Failures,
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
    trace_path_observed(scene, camera, settings, x, y, sample, &mut ())
}

/// [`trace_path`], reporting each block the path runs to `observer` (the SIMD replay's recorder).
#[inline(always)]
pub fn trace_path_observed<T: Real>(
    scene: &PackedScene,
    camera: &Camera<T>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    sample: u32,
    observer: &mut impl PathObserver,
) -> PathSample<T> {
    let (seed, max_depth) = (settings.seed, settings.max_depth);
    let pixel = y * settings.width + x;
    let mut ray = camera.ray(x, y, uniform4(pixel, sample, 0, Purpose::Camera, seed));
    let mut out = PathSample { radiance: V3::splat(T::zero()), rays: 0, failures: Failures::default() };
    let mut throughput = V3::splat(T::one());
    // When the previous hit sampled the lights: the density of this ray's direction under the
    // diffuse bounce, for the MIS weight of the emission it may find.
    let mut bsdf_pdf: Option<T> = None;
    let nee = settings.nee && !scene.lights.is_empty();
    let (robust, sphere, fresnel) =
        (scene.robust_offsets(), scene.numerics.sphere_hit, scene.numerics.fresnel);
    let t_min = T::of(scene.numerics.ray_offset.t_min());
    // The primitive the ray leaves (none for the camera ray).
    let mut from = NO_ORIGIN;
    for bounce in 0..max_depth {
        out.rays += 1;
        let Some(hit) = closest_hit_observed(&scene.nodes, &scene.primitives, &ray, t_min, sphere, observer)
        else {
            out.radiance = out.radiance + throughput.mul_elem(background(&scene.background, ray.dir));
            return out;
        };
        out.failures.self_hits += is_self_hit(&scene.primitives, from, hit.prim, &ray, hit.t) as u64;
        let prim = &scene.primitives[hit.prim as usize];
        let material = &scene.materials[prim.material as usize];
        observer.hit(material.kind);
        let sp = surface_point(prim, &ray, hit.t, robust);
        let p = sp.p;
        if material.kind == material_kind::EMISSIVE {
            let w = bsdf_pdf
                .map_or(T::one(), |pdf| emission_weight(scene, hit.prim, ray.origin, p, ray.dir, hit.t, pdf));
            out.radiance = out.radiance + throughput.mul_elem(V3::of(material.color)) * w;
            return out;
        }
        let outward = outward_normal(prim, p);
        let front_face = ray.dir.dot(outward) < T::zero();
        let normal = if front_face { outward } else { -outward };
        let u = uniform4(pixel, sample, bounce, Purpose::Scatter, seed);
        let Some(s) = scatter(material, &ray, scene.texture_point(p), normal, front_face, u, fresnel) else {
            return out;
        };
        // Direct light at diffuse hits, when the ray it stands in for (ray bounce + 2) is within
        // the depth limit.
        let lights_sampled = nee && material.kind == material_kind::LAMBERTIAN && bounce + 2 <= max_depth;
        // (A zero density, a bounce exactly along the surface, counts as no light sampling, as
        // on the GPU.)
        bsdf_pdf = lights_sampled.then(|| diffuse_pdf(normal.dot(s.dir))).filter(|&p| p > T::zero());
        // Both rays leave to the side the normal faces (the shadow ray's cosine is positive, the
        // diffuse bounce's not negative), so they share the origin, as on the GPU.
        let origin = spawn_origin(&sp, outward, s.dir, robust);
        if lights_sampled {
            let u = uniform4(pixel, sample, bounce, Purpose::Light, seed);
            if let Some(mut shadow) = next_event(scene, p, normal, u) {
                out.rays += 1;
                shadow.ray.origin = origin;
                let blocker = occluder_observed(
                    &scene.nodes,
                    &scene.primitives,
                    &shadow.ray,
                    (t_min, shadow.t_max),
                    shadow.light,
                    sphere,
                    observer,
                );
                match blocker {
                    None => {
                        out.radiance =
                            out.radiance + throughput.mul_elem(s.attenuation).mul_elem(shadow.weight)
                    }
                    Some(b) => {
                        out.failures.shadow_self_hits +=
                            is_self_hit(&scene.primitives, hit.prim, b.prim, &shadow.ray, b.t) as u64
                    }
                }
            }
        }
        throughput = throughput.mul_elem(s.attenuation);
        ray = Ray { origin, dir: s.dir };
        from = hit.prim;
    }
    // Out of depth: as in the book, the unfinished path adds nothing more.
    out.failures.depth_cut = 1;
    out
}
