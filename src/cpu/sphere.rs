//! Ray–sphere intersection; twin of `shaders/shared/sphere.wgsl`.
//!
//! The discriminant is computed as r² − |f − (f·d)d|² (Ray Tracing Gems ch. 7, "Precision
//! Improvements for Ray/Sphere Intersection") and the near root as c/q, which keeps f32 hits on
//! the book's radius-1000 ground sphere accurate where the textbook b² − 4ac form loses them.

use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::SphereRecord;

/// Distance to the nearest intersection in (t_min, t_max), if any.
#[inline(always)]
pub fn hit_sphere<T: Real>(s: &SphereRecord, ray: &Ray<T>, t_min: T, t_max: T) -> Option<T> {
    let center = V3::of(s.center);
    let r = T::of(s.radius);
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    let l = f - ray.dir * b;
    let disc = r * r - l.length_squared();
    if disc < T::zero() {
        return None;
    }
    let c = f.length_squared() - r * r;
    let sq = disc.sqrt();
    let q = if b >= T::zero() { -b - sq } else { -b + sq };
    if q == T::zero() {
        return None;
    }
    let (t0, t1) = (c / q, q);
    let (near, far) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    if near > t_min && near < t_max {
        Some(near)
    } else if far > t_min && far < t_max {
        Some(far)
    } else {
        None
    }
}

/// Outward unit normal at point `p` on the sphere.
#[inline(always)]
pub fn outward_normal<T: Real>(s: &SphereRecord, p: V3<T>) -> V3<T> {
    (p - V3::of(s.center)) / T::of(s.radius)
}
