//! Next-event estimation: a point sampled on an emitter and the shadow ray that tests it; twin of
//! `shaders/shared/light.wgsl`.
//!
//! A light is chosen from [`PackedScene::light_table`], uniformly or in proportion to its power
//! (`--light-select`), and a point on it uniformly by area, or, for a sphere seen from outside,
//! uniformly over the cone of directions it subtends (`--light-sampling solid-angle`): area
//! sampling wastes the samples on the far side, which the sphere itself hides. Emitters shine from
//! both sides (as The Next Week's `diffuse_light`). Densities are per unit solid angle at the
//! shading point, light choice included.
//!
//! Light sampling and the diffuse bounce both find the light, so the two are combined by
//! multiple importance sampling with the power heuristic (Veach 1997, as pbrt-v4): the shadow
//! ray's contribution is weighted by p_light² / (p_light² + p_bsdf²) and emission found by the
//! bounce that follows by p_bsdf² / (p_light² + p_bsdf²). Area sampling alone has a heavy tail
//! wherever a surface sees a light at close range and grazing angles (the Cornell box's ceiling
//! around its light, 1 unit away); the bounce handles those paths well.

use super::primitive::{area, outward_normal, sample_point};
use super::sphere::{cone, sample_cone};
use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::{primitive_kind, PrimitiveRecord};
use crate::light_options::{LightSampling, LightSelect};
use crate::packed_scene::PackedScene;

/// A sampled point on a light.
#[derive(Clone, Copy, Debug)]
pub struct LightSample<T> {
    pub point: V3<T>,
    /// Unit normal of the light at `point`.
    pub normal: V3<T>,
    /// Density of the direction from the shading point to `point`, per unit solid angle, light
    /// choice included (infinite or NaN when the point is seen edge-on: refused by
    /// [`next_event`]).
    pub pdf: T,
    /// The light's primitive slot.
    pub slot: u32,
}

/// The slot of the light chosen by `u0` (the table's column) and `u3` (keep its light or take
/// its alias); `None` when the scene has no lights. In f32 on every method so that all pick the
/// same light.
#[inline(always)]
pub fn choose_light(scene: &PackedScene, u0: f32, u3: f32) -> Option<u32> {
    let n = scene.light_table.len() as u32;
    if n == 0 {
        return None;
    }
    let mut i = ((u0 * n as f32) as u32).min(n - 1);
    let column = scene.light_table[i as usize];
    if scene.light_select() == LightSelect::Power && u3 >= column.threshold {
        i = column.other;
    }
    Some(scene.light_table[i as usize].slot)
}

/// Probability that [`choose_light`] picks light `p`: 1/n, or its share of the scene's power
/// (mean radiance × area / total, as the table was built).
#[inline(always)]
pub fn light_pmf<T: Real>(scene: &PackedScene, p: &PrimitiveRecord) -> T {
    if scene.light_select() == LightSelect::Power {
        let c = scene.materials[p.material as usize].color;
        let mean = (T::of(c[0]) + T::of(c[1]) + T::of(c[2])) / T::of(3.0);
        mean * area::<T>(p) / T::of(scene.light_power)
    } else {
        T::one() / T::of(scene.light_table.len() as f32)
    }
}

/// The solid-angle density, at `x`, of the direction `dir` to `point` on light `p` at squared
/// distance `dist2`, as [`sample_light`] samples it, light choice included.
#[inline(always)]
pub fn light_pdf<T: Real>(
    scene: &PackedScene,
    p: &PrimitiveRecord,
    x: V3<T>,
    point: V3<T>,
    dir: V3<T>,
    dist2: T,
) -> T {
    let pmf = light_pmf::<T>(scene, p);
    if scene.light_options.sampling == LightSampling::SolidAngle && p.kind == primitive_kind::SPHERE {
        if let Some(c) = cone::<T>(p, x) {
            return pmf / c.solid_angle();
        }
    }
    // Uniform by area: pdf_area · dist² / |cos| at the light.
    let cos_light = outward_normal(p, point).dot(dir).abs();
    pmf / area::<T>(p) * dist2 / cos_light
}

/// Chooses a light (`u[0]`, `u[3]`) and a point on it (`u[1]`, `u[2]`) for the shading point `x`;
/// `None` when the scene has no lights.
#[inline(always)]
pub fn sample_light<T: Real>(scene: &PackedScene, x: V3<T>, u: [f32; 4]) -> Option<LightSample<T>> {
    let slot = choose_light(scene, u[0], u[3])?;
    let p = &scene.primitives[slot as usize];
    if scene.light_options.sampling == LightSampling::SolidAngle && p.kind == primitive_kind::SPHERE {
        if let Some(c) = cone::<T>(p, x) {
            let (point, normal) = sample_cone(p, &c, u[1], u[2]);
            return Some(LightSample {
                point,
                normal,
                pdf: light_pmf::<T>(scene, p) / c.solid_angle(),
                slot,
            });
        }
    }
    // By area: everywhere but a sphere seen from outside with solid-angle sampling.
    let point = sample_point::<T>(p, u[1], u[2]);
    let to = point - x;
    let dist2 = to.length_squared();
    let pdf = light_pdf(scene, p, x, point, to / dist2.sqrt(), dist2);
    Some(LightSample { point, normal: outward_normal(p, point), pdf, slot })
}

/// A shadow ray and what it carries if nothing blocks it.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay<T> {
    pub ray: Ray<T>,
    /// The sampled light point's distance: the ray is unblocked when no primitive but the light
    /// itself lies in (T_MIN, t_max).
    pub t_max: T,
    /// The light's primitive slot, which the shadow ray does not test.
    pub light: u32,
    /// Radiance arriving from the light, weighted by cos at the surface over π, divided by the
    /// solid-angle density and MIS-weighted: times the throughput and albedo it is the diffuse
    /// estimate.
    pub weight: V3<T>,
}

/// The power heuristic's weight for a strategy with solid-angle density `a` against one with `b`.
#[inline(always)]
pub fn power_heuristic<T: Real>(a: T, b: T) -> T {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > T::zero() {
        a2 / (a2 + b2)
    } else {
        T::zero()
    }
}

/// The cosine-weighted diffuse bounce's density for a direction at cosine `cos` to the normal.
#[inline(always)]
pub fn diffuse_pdf<T: Real>(cos: T) -> T {
    cos.max(T::zero()) / T::PI()
}

/// MIS weight of emission from the light in `slot`, found from `origin` at distance `dist` along
/// unit `dir` (at `point`) by a diffuse bounce whose density for `dir` was `bsdf_pdf`.
#[inline(always)]
pub fn emission_weight<T: Real>(
    scene: &PackedScene,
    slot: u32,
    origin: V3<T>,
    point: V3<T>,
    dir: V3<T>,
    dist: T,
    bsdf_pdf: T,
) -> T {
    let p = &scene.primitives[slot as usize];
    power_heuristic(bsdf_pdf, light_pdf(scene, p, origin, point, dir, dist * dist))
}

/// The shadow ray from `p` (normal `normal`, facing the incoming ray) to a light point picked by
/// `u`, its contribution MIS-weighted against the diffuse bounce; `None` when there is no light
/// or the point cannot contribute (behind the surface, seen edge-on, or hidden by the light
/// itself).
#[inline(always)]
pub fn next_event<T: Real>(
    scene: &PackedScene,
    p: V3<T>,
    normal: V3<T>,
    u: [f32; 4],
) -> Option<ShadowRay<T>> {
    let l = sample_light::<T>(scene, p, u)?;
    let to = l.point - p;
    let dist2 = to.length_squared();
    let dist = dist2.sqrt();
    // (Also refuses a NaN distance.)
    if dist.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let dir = to / dist;
    let cos_surface = normal.dot(dir);
    let facing = l.normal.dot(dir);
    if !(cos_surface > T::zero() && facing.abs() > T::zero() && l.pdf > T::zero() && l.pdf <= T::max_value())
    {
        return None;
    }
    // The light's own surface is decided as closest_hit decides it: a ray from outside a sphere
    // meets its near side first, so a point facing away (the far side) is hidden by the sphere.
    // The shadow ray then skips the light's primitive and runs the whole distance, so nothing
    // else close to the light is missed either (it used to stop 1e-4 of the distance short, and
    // far-side points just past the silhouette counted as seen).
    let light = &scene.primitives[l.slot as usize];
    if light.kind == primitive_kind::SPHERE && facing > T::zero() && cone::<T>(light, p).is_some() {
        return None;
    }
    let radiance = V3::of(scene.materials[light.material as usize].color);
    let mis = power_heuristic(l.pdf, diffuse_pdf(cos_surface));
    let weight = radiance * (mis * cos_surface / (l.pdf * T::PI()));
    Some(ShadowRay { ray: Ray { origin: p, dir }, t_max: dist, light: l.slot, weight })
}
