//! Ray–sphere intersection, and sampling a sphere by the cone it subtends; twin of
//! `shaders/shared/sphere.wgsl`.
//!
//! The discriminant is computed as r² − |f − (f·d)d|² (Ray Tracing Gems ch. 7, "Precision
//! Improvements for Ray/Sphere Intersection") and the near root as c/q, which keeps f32 hits on
//! the book's radius-1000 ground sphere accurate where the textbook b² − 4ac form loses them.
//! The book's form stays selectable (`--sphere-hit book`, [`hit_sphere_book`]) to measure that.

use super::sampling::orthonormal_basis;
use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::PrimitiveRecord;

/// Distance to the nearest intersection in (t_min, t_max), if any.
#[inline(always)]
pub fn hit_sphere<T: Real>(s: &PrimitiveRecord, ray: &Ray<T>, t_min: T, t_max: T) -> Option<T> {
    let center = V3::of(s.a);
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

/// The book's quadratic (Ray Tracing in One Weekend §6.6, with h = d·(c − o)): the discriminant
/// h² − |d|²(|c − o|² − r²) cancels catastrophically when the sphere is far away or small
/// against its distance, and the near root (h − √disc)/|d|² when the origin is on the surface.
#[inline(always)]
pub fn hit_sphere_book<T: Real>(s: &PrimitiveRecord, ray: &Ray<T>, t_min: T, t_max: T) -> Option<T> {
    let r = T::of(s.radius);
    let oc = V3::of(s.a) - ray.origin;
    let a = ray.dir.length_squared();
    let h = ray.dir.dot(oc);
    let c = oc.length_squared() - r * r;
    let disc = h * h - a * c;
    if disc < T::zero() {
        return None;
    }
    let sq = disc.sqrt();
    let inside = |t: T| t > t_min && t < t_max;
    let near = (h - sq) / a;
    if inside(near) {
        return Some(near);
    }
    let far = (h + sq) / a;
    inside(far).then_some(far)
}

/// Outward unit normal at point `p` on the sphere.
#[inline(always)]
pub fn outward_normal<T: Real>(s: &PrimitiveRecord, p: V3<T>) -> V3<T> {
    (p - V3::of(s.a)) / T::of(s.radius)
}

/// The cone of directions a sphere subtends from a point outside it.
#[derive(Clone, Copy, Debug)]
pub struct Cone<T> {
    /// Unit direction from the point to the centre.
    pub axis: V3<T>,
    /// sin² of the half-angle: (radius / distance to the centre)².
    pub sin2_max: T,
    /// 1 − cos of the half-angle, as sin²/(1 + cos) (no cancellation for small cones).
    pub one_minus_cos_max: T,
}

impl<T: Real> Cone<T> {
    /// Its solid angle, 2π(1 − cos θmax).
    #[inline(always)]
    pub fn solid_angle(&self) -> T {
        T::of(2.0) * T::PI() * self.one_minus_cos_max
    }
}

/// The cone sphere `s` subtends from `x`; `None` when `x` is not outside it.
#[inline(always)]
pub fn cone<T: Real>(s: &PrimitiveRecord, x: V3<T>) -> Option<Cone<T>> {
    let to = V3::of(s.a) - x;
    let dist2 = to.length_squared();
    let r = T::of(s.radius);
    let r2 = r * r;
    // (Also refuses a NaN distance.)
    if dist2.partial_cmp(&r2) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let sin2_max = r2 / dist2;
    let cos_max = (T::one() - sin2_max).max(T::zero()).sqrt();
    Some(Cone { axis: to / dist2.sqrt(), sin2_max, one_minus_cos_max: sin2_max / (T::one() + cos_max) })
}

/// The point of sphere `s` (and its outward normal) seen along a direction uniform in the cone
/// `c` it subtends from the shading point: the first point a ray in that direction meets
/// (pbrt-v4's `Sphere::Sample`: θ uniform in cos over the cone, then the angle α at the centre
/// between the shading point and the hit, in closed form).
#[inline(always)]
pub fn sample_cone<T: Real>(s: &PrimitiveRecord, c: &Cone<T>, u1: f32, u2: f32) -> (V3<T>, V3<T>) {
    let (one, two) = (T::one(), T::of(2.0));
    let one_minus_cos = T::of(u1) * c.one_minus_cos_max;
    let cos_theta = one - one_minus_cos;
    let sin2_theta = one_minus_cos * (two - one_minus_cos);
    let cos_alpha =
        sin2_theta / c.sin2_max.sqrt() + cos_theta * (one - sin2_theta / c.sin2_max).max(T::zero()).sqrt();
    let sin_alpha = (one - cos_alpha * cos_alpha).max(T::zero()).sqrt();
    let phi = two * T::PI() * T::of(u2);
    let (t, b) = orthonormal_basis(c.axis);
    // From the centre back towards the shading point, tilted by α.
    let normal = -(t * (sin_alpha * phi.cos()) + b * (sin_alpha * phi.sin()) + c.axis * cos_alpha);
    (V3::of(s.a) + normal * T::of(s.radius), normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray<f64> {
        Ray { origin: V3::new(o[0], o[1], o[2]), dir: V3::new(d[0], d[1], d[2]).normalize() }
    }
    const UNIT: PrimitiveRecord = sphere([0.0, 0.0, 0.0], 1.0);

    const fn sphere(a: [f32; 3], radius: f32) -> PrimitiveRecord {
        PrimitiveRecord { a, kind: 0, b: [0.0; 3], radius, c: [0.0; 3], material: 0 }
    }

    #[test]
    fn hits_the_near_side_from_outside() {
        let t = hit_sphere(&UNIT, &ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), 1e-3, f64::INFINITY);
        assert!((t.unwrap() - 4.0).abs() < 1e-12);
    }

    #[test]
    fn from_inside_hits_the_far_side() {
        let r = ray([0.0, 0.2, 0.1], [1.0, 0.3, 0.0]);
        let t = hit_sphere(&UNIT, &r, 1e-3, f64::INFINITY).unwrap();
        assert!((r.at(t).length() - 1.0).abs() < 1e-12);
        assert!(r.dir.dot(outward_normal(&UNIT, r.at(t))) > 0.0, "leaving through the surface");
    }

    #[test]
    fn grazing_rays_hit_just_inside_and_miss_just_outside() {
        let inside = hit_sphere(&UNIT, &ray([-5.0, 1.0 - 1e-6, 0.0], [1.0, 0.0, 0.0]), 1e-3, f64::INFINITY);
        let t = inside.expect("a ray 1e-6 inside the silhouette hits");
        assert!((t - 5.0).abs() < 0.01);
        let outside = hit_sphere(&UNIT, &ray([-5.0, 1.0 + 1e-6, 0.0], [1.0, 0.0, 0.0]), 1e-3, f64::INFINITY);
        assert!(outside.is_none());
    }

    #[test]
    fn behind_the_origin_and_beyond_t_max_miss() {
        assert!(hit_sphere(&UNIT, &ray([0.0, 0.0, 5.0], [0.0, 0.0, 1.0]), 1e-3, f64::INFINITY).is_none());
        assert!(hit_sphere(&UNIT, &ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), 1e-3, 3.9).is_none());
    }

    #[test]
    fn f32_hits_on_the_radius_1000_ground_stay_on_the_surface() {
        // The book's ground sphere seen at a shallow angle from the final scene's camera: the
        // textbook b² − 4ac form loses most digits here in f32.
        let ground = sphere([0.0, -1000.0, 0.0], 1000.0);
        let mut s = crate::rng::Stream::new(3);
        for _ in 0..1000 {
            // Steep enough (at least ~6° down) to meet the curved ground rather than pass over it.
            let d = V3::new(-1.0, s.range(-0.35, -0.1), s.range(-0.5, 0.5)).normalize();
            let r = Ray { origin: V3::new(13.0f32, 2.0, 3.0), dir: d };
            let t =
                hit_sphere(&ground, &r, 1e-3, f32::INFINITY).expect("looking down steeply hits the ground");
            let p = r.at(t);
            // Distance from the surface, computed in f64: within a few f32 ulps of 1000.
            let dist =
                ((p.x as f64).powi(2) + (p.y as f64 + 1000.0).powi(2) + (p.z as f64).powi(2)).sqrt() - 1000.0;
            assert!(dist.abs() < 2e-3, "hit point {dist} off the surface");
        }
    }
}
