//! Closest-hit and any-hit BVH traversal; twin of `shaders/shared/bvh.wgsl` (same stack, same
//! child order).

use super::observe::PathObserver;
use super::{primitive::hit as hit_primitive, ray::Ray, real::Real, vec3::V3};
use crate::bvh::MAX_DEPTH;
use crate::layout::{BvhNode, PrimitiveRecord};
use crate::numerics::SphereHit;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<T> {
    pub t: T,
    /// Slot of the primitive in `PackedScene::primitives`.
    pub prim: u32,
}

/// Reciprocal direction with zero components replaced by a tiny signed value, so the slab test
/// never computes 0 × ∞.
#[inline(always)]
pub fn safe_inverse<T: Real>(d: V3<T>) -> V3<T> {
    let tiny = T::of(1e-20);
    d.map(|c| {
        let c = if c.abs() < tiny {
            if c < T::zero() {
                -tiny
            } else {
                tiny
            }
        } else {
            c
        };
        T::one() / c
    })
}

/// Entry distance of the ray into the node's box if it enters before `t_max`.
#[inline(always)]
fn hit_box<T: Real>(n: &BvhNode, o: V3<T>, inv: V3<T>, t_min: T, t_max: T) -> Option<T> {
    let t1 = (V3::of(n.min) - o).mul_elem(inv);
    let t2 = (V3::of(n.max) - o).mul_elem(inv);
    let near = t1.x.min(t2.x).max(t1.y.min(t2.y)).max(t1.z.min(t2.z)).max(t_min);
    let far = t1.x.max(t2.x).min(t1.y.max(t2.y)).min(t1.z.max(t2.z)).min(t_max);
    (near <= far).then_some(near)
}

/// The nearest hit in (t_min, ∞), spheres met by the `sphere` formula.
#[inline(always)]
pub fn closest_hit<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    sphere: SphereHit,
) -> Option<Hit<T>> {
    traverse(nodes, prims, ray, t_min, T::infinity(), false, NO_SKIP, sphere, &mut ())
}

/// [`closest_hit`], reporting its steps to `observer`.
#[inline(always)]
pub fn closest_hit_observed<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    sphere: SphereHit,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    observer.traversal(false);
    traverse(nodes, prims, ray, t_min, T::infinity(), false, NO_SKIP, sphere, observer)
}

/// No primitive skipped (`traverse`'s `skip`).
const NO_SKIP: u32 = u32::MAX;

/// A primitive but the one in slot `skip` (the light a shadow ray aims at) on the ray in
/// (t_min, t_max), the first the traversal finds, if any: the shadow-ray query.
#[inline(always)]
pub fn occluder<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    (t_min, t_max): (T, T),
    skip: u32,
    sphere: SphereHit,
) -> Option<Hit<T>> {
    traverse(nodes, prims, ray, t_min, t_max, true, skip, sphere, &mut ())
}

/// [`occluder`], reporting its steps to `observer`.
#[inline(always)]
pub fn occluder_observed<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    (t_min, t_max): (T, T),
    skip: u32,
    sphere: SphereHit,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    observer.traversal(true);
    traverse(nodes, prims, ray, t_min, t_max, true, skip, sphere, observer)
}

/// Whether [`occluder`] finds anything, spheres met by the stable formula.
#[inline(always)]
pub fn occluded<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    t_max: T,
    skip: u32,
) -> bool {
    occluder(nodes, prims, ray, (t_min, t_max), skip, SphereHit::Stable).is_some()
}

/// The one traversal loop: nearer child first, the farther on the stack. `any_hit` returns the
/// first hit found in (t_min, t_max) instead of the nearest; the primitive in slot `skip` is not
/// tested.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn traverse<T: Real>(
    nodes: &[BvhNode],
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    t_max: T,
    any_hit: bool,
    skip: u32,
    sphere: SphereHit,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    let inv = safe_inverse(ray.dir);
    let mut closest = t_max;
    let mut hit = None;
    let mut stack = [0u32; MAX_DEPTH];
    let mut top = 0usize;
    let mut current = 0u32;
    hit_box(&nodes[0], ray.origin, inv, t_min, closest)?;
    loop {
        let n = &nodes[current as usize];
        if n.count > 0 {
            let mut tested = 0u32;
            for slot in n.left_or_first..n.left_or_first + n.count {
                if slot == skip {
                    continue;
                }
                tested |= 1 << (slot - n.left_or_first);
                if let Some(t) = hit_primitive(&prims[slot as usize], ray, t_min, closest, sphere) {
                    closest = t;
                    hit = Some(Hit { t, prim: slot });
                    if any_hit {
                        observer.leaf(tested);
                        return hit;
                    }
                }
            }
            observer.leaf(tested);
        } else {
            observer.inner();
            let (a, b) = (current + 1, n.left_or_first);
            let ta = hit_box(&nodes[a as usize], ray.origin, inv, t_min, closest);
            let tb = hit_box(&nodes[b as usize], ray.origin, inv, t_min, closest);
            match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    // Visit the nearer child first; the farther waits on the stack.
                    let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                    stack[top] = far;
                    top += 1;
                    current = near;
                    continue;
                }
                (Some(_), None) => {
                    current = a;
                    continue;
                }
                (None, Some(_)) => {
                    current = b;
                    continue;
                }
                (None, None) => {}
            }
        }
        if top == 0 {
            return hit;
        }
        top -= 1;
        current = stack[top];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::packed_scene::PackedScene;
    use crate::scene::builtin;
    use crate::settings::Accel;

    /// The BVH and the linear loop (single leaf) find the same closest primitive at the same
    /// distance for random rays through a scene, from outside and inside spheres; any-hit
    /// queries agree with closest hits.
    #[test]
    fn bvh_and_linear_find_the_same_hits() {
        check_same_hits("rtiow-final");
    }

    #[test]
    fn bvh_and_linear_find_the_same_hits_on_quads() {
        check_same_hits("cornell");
    }

    fn check_same_hits(name: &str) {
        let scene = builtin::by_name(name).unwrap();
        let bvh = PackedScene::new(&scene, Accel::Bvh);
        let linear = PackedScene::new(&scene, Accel::None);
        assert!(bvh.nodes.len() > 10 && linear.nodes.len() == 1);
        // Rays start in the scene's bounding box.
        let root = bvh.nodes[0];
        let (lo, hi) = (glam::Vec3::from(root.min), glam::Vec3::from(root.max));
        let mut s = crate::rng::Stream::new(11);
        let mut hits = 0;
        for i in 0..20_000 {
            let origin = if i % 4 == 0 {
                // Start at a random primitive's first point (inside a sphere; on a quad).
                V3::of(linear.primitives[(s.next_f32() * linear.primitives.len() as f32) as usize].a)
            } else {
                let t = |k: usize, s: &mut crate::rng::Stream| s.range(lo[k], hi[k]);
                V3::new(t(0, &mut s), t(1, &mut s), t(2, &mut s))
            };
            let dir = V3::new(s.range(-1.0, 1.0), s.range(-1.0, 0.5), s.range(-1.0, 1.0)).normalize();
            let ray = Ray { origin, dir };
            let a = closest_hit(&bvh.nodes, &bvh.primitives, &ray, 1e-3f32, SphereHit::Stable);
            let b = closest_hit(&linear.nodes, &linear.primitives, &ray, 1e-3f32, SphereHit::Stable);
            if let Some(a) = a {
                // Any-hit agrees: something before the closest hit's far side, nothing before it.
                assert!(occluded(&bvh.nodes, &bvh.primitives, &ray, 1e-3, a.t * 1.001, u32::MAX), "ray {i}");
                assert!(!occluded(&bvh.nodes, &bvh.primitives, &ray, 1e-3, a.t * 0.999, u32::MAX), "ray {i}");
                // Skipping the primitive hit, nothing lies before it.
                assert!(!occluded(&bvh.nodes, &bvh.primitives, &ray, 1e-3, a.t, a.prim), "ray {i}");
            } else {
                assert!(
                    !occluded(&bvh.nodes, &bvh.primitives, &ray, 1e-3, f32::INFINITY, u32::MAX),
                    "ray {i}"
                );
            }
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert_eq!(a.t, b.t, "ray {i}");
                    // The slot each reports is the primitive hit at that distance. (Not always
                    // the same one: the Cornell box's boxes stand on the floor, so their bottom
                    // quads tie with it and the first found wins.)
                    for (hit, prims) in [(a, &bvh.primitives), (b, &linear.primitives)] {
                        let t = super::hit_primitive(
                            &prims[hit.prim as usize],
                            &ray,
                            1e-3,
                            f32::INFINITY,
                            SphereHit::Stable,
                        );
                        assert_eq!(t, Some(hit.t), "ray {i}");
                    }
                }
                (None, None) => {}
                _ => panic!("ray {i}: BVH {a:?} vs linear {b:?}"),
            }
        }
        assert!(hits > 10_000, "most rays hit something ({hits})");
    }
}
