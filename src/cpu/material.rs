//! Scattering by the book's materials; twin of `shaders/shared/material.wgsl`.

use super::{ray::Ray, real::Real, sampling::unit_vector, vec3::V3};
use crate::layout::{material_kind, MaterialRecord};

/// Where a path goes next and how much of it survives.
#[derive(Clone, Copy, Debug)]
pub struct Scatter<T> {
    pub attenuation: V3<T>,
    pub dir: V3<T>,
}

#[inline(always)]
pub fn reflect<T: Real>(v: V3<T>, n: V3<T>) -> V3<T> {
    v - n * (T::of(2.0) * v.dot(n))
}

#[inline(always)]
pub fn refract<T: Real>(uv: V3<T>, n: V3<T>, eta_ratio: T) -> V3<T> {
    let cos_theta = (-uv).dot(n).min(T::one());
    let perp = (uv + n * cos_theta) * eta_ratio;
    let parallel = n * -(T::one() - perp.length_squared()).abs().sqrt();
    perp + parallel
}

/// Schlick's approximation of Fresnel reflectance.
#[inline(always)]
pub fn reflectance<T: Real>(cosine: T, eta_ratio: T) -> T {
    let r0 = (T::one() - eta_ratio) / (T::one() + eta_ratio);
    let r0 = r0 * r0;
    r0 + (T::one() - r0) * (T::one() - cosine).powi(5)
}

/// Scatters `ray` at a surface with shading normal `normal` (facing the ray), `front_face` true
/// when the ray arrived from outside. `u` are the bounce's three scatter numbers. `None`: the
/// path is absorbed (or the surface only emits).
#[inline(always)]
pub fn scatter<T: Real>(
    m: &MaterialRecord,
    ray: &Ray<T>,
    normal: V3<T>,
    front_face: bool,
    u: [f32; 4],
) -> Option<Scatter<T>> {
    let color = V3::of(m.color);
    match m.kind {
        material_kind::LAMBERTIAN => {
            let d = normal + unit_vector(u[0], u[1]);
            // The book's near_zero guard: a sample opposite the normal falls back to it.
            let tiny = T::of(1e-8);
            let dir = if d.x.abs() < tiny && d.y.abs() < tiny && d.z.abs() < tiny { normal } else { d };
            Some(Scatter { attenuation: color, dir: dir.normalize() })
        }
        material_kind::METAL => {
            let fuzz = T::of(m.param);
            let dir = reflect(ray.dir, normal) + unit_vector::<T>(u[0], u[1]) * fuzz;
            if dir.dot(normal) <= T::zero() {
                return None;
            }
            Some(Scatter { attenuation: color, dir: dir.normalize() })
        }
        material_kind::DIELECTRIC => {
            let ior = T::of(m.param);
            let ri = if front_face { T::one() / ior } else { ior };
            let cos_theta = (-ray.dir).dot(normal).min(T::one());
            let sin_theta = (T::one() - cos_theta * cos_theta).max(T::zero()).sqrt();
            let cannot_refract = ri * sin_theta > T::one();
            let dir = if cannot_refract || reflectance(cos_theta, ri) > T::of(u[2]) {
                reflect(ray.dir, normal)
            } else {
                refract(ray.dir, normal, ri)
            };
            Some(Scatter { attenuation: V3::splat(T::one()), dir: dir.normalize() })
        }
        _ => None,
    }
}
