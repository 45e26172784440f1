//! Next-event estimation: a point sampled on an emitter and the shadow ray that tests it; twin of
//! `shaders/shared/light.wgsl`.
//!
//! A light is chosen uniformly from [`PackedScene::lights`] and a point on it uniformly by area,
//! so the area density is 1 / (lights × area). Emitters shine from both sides (as The Next Week's
//! `diffuse_light`), hence |cos| at the light.
//!
//! Light sampling and the diffuse bounce both find the light, so the two are combined by
//! multiple importance sampling with the power heuristic (Veach 1997, as pbrt-v4): the shadow
//! ray's contribution is weighted by p_light² / (p_light² + p_bsdf²) and emission found by the
//! bounce that follows by p_bsdf² / (p_light² + p_bsdf²), densities in solid angle. Area sampling
//! alone has a heavy tail wherever a surface sees a light at close range and grazing angles
//! (the Cornell box's ceiling around its light, 1 unit away); the bounce handles those paths well.

use super::primitive::{area, outward_normal, sample_point};
use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::PrimitiveRecord;
use crate::packed_scene::PackedScene;

/// A shadow ray stops this fraction of the distance short of the light, so that it does not
/// find the light itself.
pub const SHADOW_SHORTEN: f32 = 1e-4;

/// A sampled point on a light.
#[derive(Clone, Copy, Debug)]
pub struct LightSample<T> {
    pub point: V3<T>,
    /// Unit normal of the light at `point`.
    pub normal: V3<T>,
    /// Density of `point` per unit area, light choice included.
    pub pdf_area: T,
    /// The light's primitive slot.
    pub slot: u32,
}

/// Picks a light (`u[0]`) and a point on it (`u[1]`, `u[2]`); `None` when the scene has none.
#[inline(always)]
pub fn sample_light<T: Real>(scene: &PackedScene, u: [f32; 4]) -> Option<LightSample<T>> {
    let n = scene.lights.len() as u32;
    if n == 0 {
        return None;
    }
    // In f32 on every method so that all pick the same light.
    let i = ((u[0] * n as f32) as u32).min(n - 1);
    let slot = scene.lights[i as usize];
    let p = &scene.primitives[slot as usize];
    let point = sample_point::<T>(p, u[1], u[2]);
    let normal = outward_normal(p, point);
    Some(LightSample { point, normal, pdf_area: pdf_area(scene, p), slot })
}

/// The area density of a point sampled on light `p`: uniform light choice, then uniform by area.
#[inline(always)]
fn pdf_area<T: Real>(scene: &PackedScene, p: &PrimitiveRecord) -> T {
    T::one() / (T::of(scene.lights.len() as f32) * area::<T>(p))
}

/// A shadow ray and what it carries if nothing blocks it.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay<T> {
    pub ray: Ray<T>,
    /// The ray is unblocked when nothing is hit in (T_MIN, t_max).
    pub t_max: T,
    /// Radiance arriving from the light, weighted by cos at the surface over π, divided by the
    /// solid-angle density and MIS-weighted: times the throughput and albedo it is the diffuse
    /// estimate.
    pub weight: V3<T>,
}

/// The power heuristic's weight for a strategy with solid-angle density `a` against one with `b`,
/// each given times the same positive factor (so no density needs dividing by a cosine).
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

/// MIS weight of emission from the light in `slot`, found at distance `dist` along unit `dir` by
/// a diffuse bounce whose density for `dir` was `bsdf_pdf`.
#[inline(always)]
pub fn emission_weight<T: Real>(
    scene: &PackedScene,
    slot: u32,
    point: V3<T>,
    dir: V3<T>,
    dist: T,
    bsdf_pdf: T,
) -> T {
    let p = &scene.primitives[slot as usize];
    let cos_light = outward_normal(p, point).dot(dir).abs();
    // p_light = pdf_area · dist² / cos_light; both densities times cos_light.
    power_heuristic(bsdf_pdf * cos_light, pdf_area::<T>(scene, p) * dist * dist)
}

/// The shadow ray from `p` (normal `normal`, facing the incoming ray) to a light point picked by
/// `u`, its contribution MIS-weighted against the diffuse bounce; `None` when there is no light
/// or the point cannot contribute (behind the surface, or seen edge-on).
#[inline(always)]
pub fn next_event<T: Real>(
    scene: &PackedScene,
    p: V3<T>,
    normal: V3<T>,
    u: [f32; 4],
) -> Option<ShadowRay<T>> {
    let l = sample_light::<T>(scene, u)?;
    let to = l.point - p;
    let dist2 = to.length_squared();
    let dist = dist2.sqrt();
    // (Also refuses a NaN distance.)
    if dist.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let dir = to / dist;
    let cos_surface = normal.dot(dir);
    let cos_light = l.normal.dot(dir).abs();
    if !(cos_surface > T::zero() && cos_light > T::zero()) {
        return None;
    }
    let radiance = V3::of(scene.materials[scene.primitives[l.slot as usize].material as usize].color);
    let mis = power_heuristic(l.pdf_area * dist2, diffuse_pdf(cos_surface) * cos_light);
    let weight = radiance * (mis * cos_surface * cos_light / (dist2 * l.pdf_area * T::PI()));
    Some(ShadowRay { ray: Ray { origin: p, dir }, t_max: dist * (T::one() - T::of(SHADOW_SHORTEN)), weight })
}
