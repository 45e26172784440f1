//! What every shape answers: hit distance, normal, area and a uniform point on it; twin of
//! `shaders/shared/primitive.wgsl`.

use super::planar::{hit_planar, planar_normal};
use super::sampling::unit_vector;
use super::sphere::{hit_sphere, hit_sphere_book, outward_normal as sphere_normal};
use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::{primitive_kind, PrimitiveRecord};
use crate::numerics::SphereHit;
/// Surface area (its own module: packed_scene weighs lights by it too).
pub use crate::primitive_area::area;

/// Distance to the nearest hit in (t_min, t_max), if any; spheres by the `sphere` formula.
#[inline(always)]
pub fn hit<T: Real>(p: &PrimitiveRecord, ray: &Ray<T>, t_min: T, t_max: T, sphere: SphereHit) -> Option<T> {
    if p.kind == primitive_kind::SPHERE {
        match sphere {
            SphereHit::Stable => hit_sphere(p, ray, t_min, t_max),
            SphereHit::Book => hit_sphere_book(p, ray, t_min, t_max),
        }
    } else {
        hit_planar(p, ray, t_min, t_max)
    }
}

/// Unit normal at `point`: outward for a sphere, `b × c` for a quad or triangle.
#[inline(always)]
pub fn outward_normal<T: Real>(p: &PrimitiveRecord, point: V3<T>) -> V3<T> {
    if p.kind == primitive_kind::SPHERE {
        sphere_normal(p, point)
    } else {
        planar_normal(p)
    }
}

/// A point distributed uniformly by area, from two uniform numbers.
#[inline(always)]
pub fn sample_point<T: Real>(p: &PrimitiveRecord, u1: f32, u2: f32) -> V3<T> {
    let (a, b, c) = (V3::<T>::of(p.a), V3::<T>::of(p.b), V3::<T>::of(p.c));
    match p.kind {
        primitive_kind::SPHERE => a + unit_vector::<T>(u1, u2) * T::of(p.radius),
        primitive_kind::QUAD => a + b * T::of(u1) + c * T::of(u2),
        _ => {
            // (1 − √u1, √u1(1 − u2), √u1·u2): uniform barycentrics (Shirley's warp).
            let s = T::of(u1).sqrt();
            a + b * (s * (T::one() - T::of(u2))) + c * (s * T::of(u2))
        }
    }
}
