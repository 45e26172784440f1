//! Ray–quad and ray–triangle intersection; twin of `shaders/shared/planar.wgsl`.
//!
//! Both are a plane hit followed by a test of the hit's planar coordinates (α, β) in the frame of
//! the edges, as in Ray Tracing: The Next Week: `p = a + α·b + β·c`, with `w = n / (n·n)` so that
//! α = w·(h × c) and β = w·(b × h) for h = p − a. A quad keeps α, β in [0, 1]; a triangle keeps
//! α, β ≥ 0 and α + β ≤ 1.

use super::{ray::Ray, real::Real, vec3::V3};
use crate::layout::{primitive_kind, PrimitiveRecord};

/// Rays closer to parallel than this (cosine to the plane's normal, squared) miss: their `t`
/// would be meaningless.
pub const PARALLEL_COS2: f32 = 1e-16;

/// Distance to the hit in (t_min, t_max), if any.
#[inline(always)]
pub fn hit_planar<T: Real>(p: &PrimitiveRecord, ray: &Ray<T>, t_min: T, t_max: T) -> Option<T> {
    let (a, u, v) = (V3::of(p.a), V3::of(p.b), V3::of(p.c));
    let n = u.cross(v);
    let nn = n.dot(n);
    let denom = n.dot(ray.dir);
    if denom * denom <= T::of(PARALLEL_COS2) * nn {
        return None;
    }
    let t = n.dot(a - ray.origin) / denom;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let h = ray.at(t) - a;
    let w = n / nn;
    let alpha = w.dot(h.cross(v));
    let beta = w.dot(u.cross(h));
    let (zero, one) = (T::zero(), T::one());
    let inside = if p.kind == primitive_kind::QUAD {
        alpha >= zero && alpha <= one && beta >= zero && beta <= one
    } else {
        alpha >= zero && beta >= zero && alpha + beta <= one
    };
    inside.then_some(t)
}

/// The unit normal `b × c` (counter-clockwise corners face the viewer).
#[inline(always)]
pub fn planar_normal<T: Real>(p: &PrimitiveRecord) -> V3<T> {
    V3::of(p.b).cross(V3::of(p.c)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prim(kind: u32, a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> PrimitiveRecord {
        PrimitiveRecord { a, kind, b, radius: 0.0, c, material: 0 }
    }

    fn down_at(x: f64, y: f64) -> Ray<f64> {
        Ray { origin: V3::new(x, y, 5.0), dir: V3::new(0.0, 0.0, -1.0) }
    }

    #[test]
    fn quad_and_triangle_cover_their_own_parallelogram_and_half() {
        let quad = prim(primitive_kind::QUAD, [0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let tri = prim(primitive_kind::TRIANGLE, [0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let inf = f64::INFINITY;
        for (x, y, in_quad, in_tri) in [
            (0.5, 0.25, true, true),
            (1.5, 0.75, true, false),
            (1.9, 0.01, true, true),
            (2.1, 0.5, false, false),
            (0.5, -0.01, false, false),
            (-0.01, 0.5, false, false),
        ] {
            let q = hit_planar(&quad, &down_at(x, y), 1e-3, inf);
            let t = hit_planar(&tri, &down_at(x, y), 1e-3, inf);
            assert_eq!(q.is_some(), in_quad, "quad at ({x}, {y})");
            assert_eq!(t.is_some(), in_tri, "triangle at ({x}, {y})");
            if let Some(t) = q {
                assert!((t - 5.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn both_sides_hit_parallel_and_behind_miss() {
        let quad = prim(primitive_kind::QUAD, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let up = Ray { origin: V3::new(0.5, 0.5, -2.0), dir: V3::new(0.0, 0.0, 1.0) };
        assert!((hit_planar(&quad, &up, 1e-3, f64::INFINITY).unwrap() - 2.0).abs() < 1e-12, "back side");
        let parallel = Ray { origin: V3::new(-1.0, 0.5, 0.0), dir: V3::new(1.0, 0.0, 0.0) };
        assert!(hit_planar(&quad, &parallel, 1e-3, f64::INFINITY).is_none());
        let away = Ray { origin: V3::new(0.5, 0.5, 2.0), dir: V3::new(0.0, 0.0, 1.0) };
        assert!(hit_planar(&quad, &away, 1e-3, f64::INFINITY).is_none());
        assert!(hit_planar(&quad, &down_at(0.5, 0.5), 1e-3, 4.9).is_none(), "beyond t_max");
        let n: V3<f64> = planar_normal(&quad);
        assert_eq!((n.x, n.y, n.z), (0.0, 0.0, 1.0));
    }
}
