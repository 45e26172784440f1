//! Where a ray leaves a surface (`--ray-offset`): the hit point, a conservative bound on its
//! rounding error, and the origin moved off the surface by that bound; twin of
//! `shaders/shared/offset.wgsl`.
//!
//! With `tmin` the hit point is `o + t·d` and the next ray starts there, hits nearer than t_min
//! ignored (the book). With `robust` (pbrt-v4's `OffsetRayOrigin`, Pharr et al. 2023 §6.8) the
//! point is recomputed from the surface — a sphere's reprojected onto it, a quad's or
//! triangle's as `a + α·b + β·c` — with an error bound `err` per axis, and the next ray starts at
//! the point moved along the geometric normal by `|n|·err`, rounded away from the surface, so
//! that it is on the side the ray leaves by whatever rounding did; hits need only t > 0.

use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::{primitive_kind, PrimitiveRecord};

/// γ(n) = n·u / (1 − n·u) for unit roundoff u: the bound on n successive roundings' relative
/// error (Higham).
#[inline(always)]
pub fn gamma<T: Real>(n: f32) -> T {
    let nu = T::of(n) * T::unit_roundoff();
    nu / (T::one() - nu)
}

/// A hit point and the bound on its rounding error per axis (zero with `tmin`).
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint<T> {
    pub p: V3<T>,
    pub err: V3<T>,
}

/// The point where `ray` meets primitive `prim` at `t`: `o + t·d` (`robust == false`), or
/// recomputed from the surface with its error bound.
#[inline(always)]
pub fn surface_point<T: Real>(prim: &PrimitiveRecord, ray: &Ray<T>, t: T, robust: bool) -> SurfacePoint<T> {
    let p = ray.at(t);
    if !robust {
        return SurfacePoint { p, err: V3::splat(T::zero()) };
    }
    let a = V3::<T>::of(prim.a);
    if prim.kind == primitive_kind::SPHERE {
        // Reprojected onto the sphere: the error of o + t·d (which grows with t) is replaced by
        // a few roundings of the reprojection and of adding the centre back (pbrt-v4's γ(5)
        // for the reprojection, here plus the translation by the centre).
        let l = p - a;
        let l = l * (T::of(prim.radius) / l.length());
        let err = l.map(|c| c.abs()) * gamma::<T>(6.0) + a.map(|c| c.abs()) * gamma::<T>(2.0);
        return SurfacePoint { p: a + l, err };
    }
    // Quad or triangle: the plane point's coordinates in the frame of the edges, then the point
    // from them (pbrt-v4 bounds a triangle's barycentric sum by γ(7)).
    let (b, c) = (V3::<T>::of(prim.b), V3::<T>::of(prim.c));
    let n = b.cross(c);
    let w = n / n.dot(n);
    let h = p - a;
    let (ab, ac) = (b * w.dot(h.cross(c)), c * w.dot(b.cross(h)));
    let abs = |v: V3<T>| v.map(|x| x.abs());
    SurfacePoint { p: a + ab + ac, err: (abs(a) + abs(ab) + abs(ac)) * gamma::<T>(7.0) }
}

/// The origin of a ray leaving `sp` in direction `dir`, for geometric unit normal `n` (either
/// orientation): `sp.p` itself with `tmin` (zero error), else moved along ±n, to the side `dir`
/// goes, by the error bound projected on n, and rounded one ulp further away.
#[inline(always)]
pub fn spawn_origin<T: Real>(sp: &SurfacePoint<T>, n: V3<T>, dir: V3<T>, robust: bool) -> V3<T> {
    if !robust {
        return sp.p;
    }
    let d = n.x.abs() * sp.err.x + n.y.abs() * sp.err.y + n.z.abs() * sp.err.z;
    let offset = if dir.dot(n) < T::zero() { -(n * d) } else { n * d };
    let po = sp.p + offset;
    // From 0, the smallest normal rather than a subnormal, which GPUs may flush to zero (as
    // shaders/shared/offset.wgsl does).
    let away = |p: T, o: T| {
        if o > T::zero() {
            if p == T::zero() {
                T::min_positive_value()
            } else {
                p.next_up()
            }
        } else if o < T::zero() {
            if p == T::zero() {
                -T::min_positive_value()
            } else {
                p.next_down()
            }
        } else {
            p
        }
    };
    V3::new(away(po.x, offset.x), away(po.y, offset.y), away(po.z, offset.z))
}

/// No primitive: what a camera ray left.
pub const NO_ORIGIN: u32 = 0xffff_fffe;

/// Whether a ray that left primitive `from` and met primitive `hit` at `t` met its own surface
/// where leaving it cannot: any hit on the same quad or triangle (flat), or on the same sphere
/// nearer than half the chord from the origin, −(o − c)·d (the far side lies a whole chord
/// away; a ray leaving outwards has no chord, and no hit on it is real).
#[inline(always)]
pub fn is_self_hit<T: Real>(prims: &[PrimitiveRecord], from: u32, hit: u32, ray: &Ray<T>, t: T) -> bool {
    if from != hit {
        return false;
    }
    let p = &prims[hit as usize];
    if p.kind != primitive_kind::SPHERE {
        return true;
    }
    let half_chord = -(ray.origin - V3::of(p.a)).dot(ray.dir);
    half_chord.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) || t < half_chord
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(a: [f32; 3], radius: f32) -> PrimitiveRecord {
        PrimitiveRecord { a, kind: primitive_kind::SPHERE, b: [0.0; 3], radius, c: [0.0; 3], material: 0 }
    }

    #[test]
    fn robust_origins_land_on_the_side_the_ray_leaves_by() {
        // A sphere far from the origin (its centre's coordinates 1e5, radius 1): o + t·d lands
        // off the surface by many ulps, the robust origin on the right side always.
        let s = sphere([1e5, -2e5, 3e5], 1.0);
        let mut rng = crate::rng::Stream::new(7);
        for _ in 0..2000 {
            let d = V3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize();
            let o = V3::<f32>::of(s.a) - d * 10.0;
            let r = Ray { origin: o, dir: d };
            let Some(t) = super::super::sphere::hit_sphere(&s, &r, 0.0, f32::INFINITY) else { continue };
            let sp = surface_point(&s, &r, t, true);
            let n = (sp.p - V3::of(s.a)).normalize();
            for (dir, outside) in [(n, true), (-n, false)] {
                let q = spawn_origin(&sp, n, dir, true);
                // Distance from the centre in f64: strictly outside / inside.
                let f = |i: usize| q.to_f64()[i] - s.a[i] as f64;
                let dist = (f(0) * f(0) + f(1) * f(1) + f(2) * f(2)).sqrt();
                assert_eq!(dist > 1.0, outside, "origin at {dist} from the centre");
            }
        }
    }

    #[test]
    fn self_hits_are_own_flat_surfaces_and_the_near_root_of_spheres() {
        let s = sphere([0.0, 0.0, 0.0], 1.0);
        let prims = [s];
        // From the surface inwards: the far side, 2 away, is real; a hit at 1e-6 is not.
        let r = Ray { origin: V3::new(0.0f64, 0.0, -1.0), dir: V3::new(0.0, 0.0, 1.0) };
        assert!(!is_self_hit(&prims, 0, 0, &r, 2.0));
        assert!(is_self_hit(&prims, 0, 0, &r, 1e-6));
        // Outwards: every hit on the sphere is a self-hit.
        let out = Ray { origin: V3::new(0.0f64, 0.0, -1.0), dir: V3::new(0.0, 0.0, -1.0) };
        assert!(is_self_hit(&prims, 0, 0, &out, 1e-6));
        assert!(!is_self_hit(&prims, NO_ORIGIN, 0, &r, 1e-6));
    }
}
