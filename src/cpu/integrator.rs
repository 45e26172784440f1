//! One path from camera to light: the book's `ray_color` as a loop; twin of the megakernel's
//! `trace_path` in `shaders/megakernel.wgsl`.

use super::bvh::{closest_hit, occluder};
use super::image_texture::surface_uv;
use super::light::{diffuse_pdf, emission_weight, next_event};
use super::observe::PathObserver;
use super::offset::{is_self_hit, spawn_origin, surface_point, NO_ORIGIN};
use super::texture::TexturePoint;
use super::{background::background, camera::Camera, material::scatter};
use super::{primitive::outward_normal, ray::Ray, real::Real, vec3::V3};
use crate::layout::{material_kind, texture_kind};
use crate::numerics::{Failures, SphereHit};
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

/// Radiance carried by sample `sample` of pixel (x, y), and the rays it took, reporting each
/// block the path runs to `observer` (the SIMD replay's recorder; `&mut ()`: none).
#[inline(always)]
pub fn trace_path<T: Real>(
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
        let Some(hit) = closest_hit(scene.bvh_nodes(), &scene.primitives, &ray, t_min, sphere, observer)
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
        // Texture coordinates only for an image (other textures never read them, as on the GPU).
        let uv = if material.texture == texture_kind::IMAGE {
            surface_uv(prim, &scene.uvs[hit.prim as usize], p)
        } else {
            [T::zero(); 2]
        };
        let at = TexturePoint { p: scene.texture_point(p), uv, texels: &scene.texels };
        let Some(s) = scatter(material, &ray, &at, normal, front_face, u, fresnel) else {
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
            let light =
                shadow_ray(scene, (p, normal, origin), hit.prim, u, (t_min, sphere), observer, &mut out);
            if let Some(w) = light {
                out.radiance = out.radiance + throughput.mul_elem(s.attenuation).mul_elem(w);
            }
        }
        throughput = throughput.mul_elem(s.attenuation);
        // Russian roulette decides after this hit's shadow ray, before the next ray. Not at the
        // last bounce, which ends the path anyway (as a depth cut, as on the GPU).
        if settings.roulette && bounce + 1 < max_depth {
            let u = uniform4(pixel, sample, bounce, Purpose::Roulette, seed)[0];
            match roulette(throughput, bounce, u) {
                Some(t) => throughput = t,
                None => return out,
            }
        }
        ray = Ray { origin, dir: s.dir };
        from = hit.prim;
    }
    // Out of depth: as in the book, the unfinished path adds nothing more.
    out.failures.depth_cut = 1;
    out
}

/// Next-event estimation's shadow ray from `origin`, for hit point `p` with `normal` on
/// primitive `prim`: the sampled light's weighted radiance where nothing blocks it. Counts the
/// ray, and a blocker that is the surface itself as a shadow self-hit, in `out`.
#[inline(always)]
fn shadow_ray<T: Real>(
    scene: &PackedScene,
    (p, normal, origin): (V3<T>, V3<T>, V3<T>),
    prim: u32,
    u: [f32; 4],
    (t_min, sphere): (T, SphereHit),
    observer: &mut impl PathObserver,
    out: &mut PathSample<T>,
) -> Option<V3<T>> {
    let mut shadow = next_event(scene, p, normal, u)?;
    out.rays += 1;
    shadow.ray.origin = origin;
    let range = (t_min, shadow.t_max);
    match occluder(scene.bvh_nodes(), &scene.primitives, &shadow.ray, range, shadow.light, sphere, observer) {
        None => Some(shadow.weight),
        Some(b) => {
            out.failures.shadow_self_hits +=
                is_self_hit(&scene.primitives, prim, b.prim, &shadow.ray, b.t) as u64;
            None
        }
    }
}

/// pbrt-v4's Russian roulette (`PathIntegrator::Li`) at hit `bounce` (0: the camera ray's hit),
/// given the throughput with this hit's attenuation in it and a uniform `u`: the path's new
/// throughput, or `None` when it ends here. pbrt's `depth > 1` counts bounces taken, this one
/// included, so roulette starts at the second hit, `bounce >= 1`. pbrt tests `beta * etaScale`
/// to keep refraction's η² radiance scaling out of the decision; the book's dielectric does not
/// scale radiance (attenuation 1 both ways), so etaScale is 1 here. Twin of `roulette` in
/// `shaders/shared/material.wgsl`.
#[inline(always)]
pub fn roulette<T: Real>(throughput: V3<T>, bounce: u32, u: f32) -> Option<V3<T>> {
    let largest = throughput.x.max(throughput.y).max(throughput.z);
    // pbrt's test, `largest < 1`, written so that clippy accepts it.
    if bounce == 0 || largest.partial_cmp(&T::one()) != Some(std::cmp::Ordering::Less) {
        return Some(throughput);
    }
    let q = (T::one() - largest).max(T::zero());
    if T::of(u) < q {
        return None;
    }
    Some(throughput / (T::one() - q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roulette_follows_pbrt_v4() {
        let t = V3::new(0.25f64, 0.5, 0.125);
        // Never at the first hit, nor once the throughput's largest component reaches 1.
        assert_eq!(roulette(t, 0, 0.0), Some(t));
        assert_eq!(roulette(V3::new(1.0f64, 0.1, 0.1), 3, 0.0), Some(V3::new(1.0, 0.1, 0.1)));
        // Largest 0.5: ends with probability 0.5; a survivor is divided by 0.5.
        assert_eq!(roulette(t, 1, 0.49), None);
        assert_eq!(roulette(t, 1, 0.5), Some(V3::new(0.5, 1.0, 0.25)));
        // A black throughput always ends (q = 1), so nothing is ever divided by 0.
        assert_eq!(roulette(V3::splat(0.0f64), 5, 0.999_999_9), None);
    }

    #[test]
    fn roulette_keeps_the_expected_throughput() {
        // E[throughput after roulette] = throughput: the estimator stays unbiased.
        let t = V3::new(0.3f64, 0.05, 0.2);
        let n = 100_000;
        let sum =
            (0..n).map(|i| roulette(t, 2, (i as f32 + 0.5) / n as f32).map_or(0.0, |v| v.x)).sum::<f64>();
        assert!((sum / n as f64 - 0.3).abs() < 1e-4, "mean {}", sum / n as f64);
    }
}
