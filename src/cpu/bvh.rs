//! Closest-hit and any-hit BVH traversal; twin of `shaders/shared/bvh.wgsl` (same stack, same
//! child order). The binary layout's loop is here; the others' in `bvh_aila_laine.rs` and
//! `bvh_wide.rs`, each the twin of its WGSL file.

use super::observe::PathObserver;
use super::{primitive::hit as hit_primitive, ray::Ray, real::Real, vec3::V3};
use crate::bvh::{BvhRef, MAX_DEPTH};
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
    hit_bounds(n.min, n.max, o, inv, t_min, t_max)
}

/// Entry distance of the ray into the box (min, max) if it enters before `t_max`: the one slab
/// test of every layout, so a box that contains another is entered by every ray entering it.
#[inline(always)]
pub fn hit_bounds<T: Real>(
    min: [f32; 3],
    max: [f32; 3],
    o: V3<T>,
    inv: V3<T>,
    t_min: T,
    t_max: T,
) -> Option<T> {
    let t1 = (V3::of(min) - o).mul_elem(inv);
    let t2 = (V3::of(max) - o).mul_elem(inv);
    let near = t1.x.min(t2.x).max(t1.y.min(t2.y)).max(t1.z.min(t2.z)).max(t_min);
    let far = t1.x.max(t2.x).min(t1.y.max(t2.y)).min(t1.z.max(t2.z)).min(t_max);
    (near <= far).then_some(near)
}

/// One traversal's question: the ray, its interval, whether any hit will do (a shadow ray),
/// the primitive slot not to test (`NO_SKIP` for none) and the sphere formula.
pub struct Query<'a, T> {
    pub prims: &'a [PrimitiveRecord],
    pub ray: &'a Ray<T>,
    pub t_min: T,
    pub t_max: T,
    pub any_hit: bool,
    pub skip: u32,
    pub sphere: SphereHit,
}

impl<T: Real> Query<'_, T> {
    /// The primitive in `slot` hit in (t_min, t_max), `t_max` being the closest hit so far.
    #[inline(always)]
    pub fn hit(&self, slot: u32, t_max: T) -> Option<T> {
        hit_primitive(&self.prims[slot as usize], self.ray, self.t_min, t_max, self.sphere)
    }

    /// Tests a leaf's primitives, `slots` with each one's bit in the observer's mask, narrowing
    /// `closest` and `hit`; true where an any-hit query found one (the traversal ends). Every
    /// layout's leaf loop.
    #[inline(always)]
    pub fn leaf(
        &self,
        slots: impl Iterator<Item = (u32, u32)>,
        closest: &mut T,
        hit: &mut Option<Hit<T>>,
        observer: &mut impl PathObserver,
    ) -> bool {
        let mut tested = 0u32;
        for (slot, bit) in slots {
            if slot == self.skip {
                continue;
            }
            tested |= 1 << bit;
            if let Some(t) = self.hit(slot, *closest) {
                *closest = t;
                *hit = Some(Hit { t, prim: slot });
                if self.any_hit {
                    break;
                }
            }
        }
        observer.leaf(tested);
        self.any_hit && hit.is_some()
    }
}

/// The child to visit next of two, `a` and `b` with their entry distances: the nearer where both
/// are hit (the farther pushed on `stack`), the one hit, or none.
#[inline(always)]
pub fn nearer_child<N: Copy, T: Real>(
    (a, ta): (N, Option<T>),
    (b, tb): (N, Option<T>),
    stack: &mut [N],
    top: &mut usize,
    observer: &mut impl PathObserver,
) -> Option<N> {
    match (ta, tb) {
        (Some(ta), Some(tb)) => {
            let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
            stack[*top] = far;
            *top += 1;
            observer.stack(*top);
            Some(near)
        }
        (Some(_), None) => Some(a),
        (None, Some(_)) => Some(b),
        (None, None) => None,
    }
}

/// The node on top of the traversal stack, taken off it; none when the stack is empty (the
/// traversal is over).
#[inline(always)]
pub fn pop<N: Copy>(stack: &[N], top: &mut usize) -> Option<N> {
    *top = top.checked_sub(1)?;
    Some(stack[*top])
}

/// The nearest hit in (t_min, ∞), spheres met by the `sphere` formula, reporting its steps to
/// `observer` (`&mut ()`: none).
#[inline(always)]
pub fn closest_hit<T: Real>(
    bvh: BvhRef,
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    sphere: SphereHit,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    observer.traversal(false);
    let q = Query { prims, ray, t_min, t_max: T::infinity(), any_hit: false, skip: NO_SKIP, sphere };
    traverse(bvh, &q, observer)
}

/// No primitive skipped (`Query::skip`).
pub const NO_SKIP: u32 = u32::MAX;

/// A primitive but the one in slot `skip` (the light a shadow ray aims at) on the ray in
/// (t_min, t_max), the first the traversal finds, if any: the shadow-ray query, reporting its
/// steps to `observer` (`&mut ()`: none).
#[inline(always)]
pub fn occluder<T: Real>(
    bvh: BvhRef,
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    (t_min, t_max): (T, T),
    skip: u32,
    sphere: SphereHit,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    observer.traversal(true);
    let q = Query { prims, ray, t_min, t_max, any_hit: true, skip, sphere };
    traverse(bvh, &q, observer)
}

/// Whether [`occluder`] finds anything, spheres met by the stable formula.
#[inline(always)]
pub fn occluded<T: Real>(
    bvh: BvhRef,
    prims: &[PrimitiveRecord],
    ray: &Ray<T>,
    t_min: T,
    t_max: T,
    skip: u32,
) -> bool {
    occluder(bvh, prims, ray, (t_min, t_max), skip, SphereHit::Stable, &mut ()).is_some()
}

/// The query on the layout's own traversal loop.
#[inline(always)]
fn traverse<T: Real>(bvh: BvhRef, q: &Query<T>, observer: &mut impl PathObserver) -> Option<Hit<T>> {
    match bvh {
        BvhRef::Binary(nodes) => traverse_binary(nodes, q, observer),
        BvhRef::AilaLaine(nodes) => super::bvh_aila_laine::traverse(nodes, q, observer),
        BvhRef::Wide(nodes) => super::bvh_wide::traverse(nodes, q, observer),
    }
}

/// The binary layout's loop: nearer child first, the farther on the stack. `any_hit` returns
/// the first hit found in (t_min, t_max) instead of the nearest; the primitive in slot `skip` is
/// not tested.
#[inline(always)]
fn traverse_binary<T: Real>(
    nodes: &[BvhNode],
    q: &Query<T>,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    let ray = q.ray;
    let inv = safe_inverse(ray.dir);
    let mut closest = q.t_max;
    let mut hit = None;
    let mut stack = [0u32; MAX_DEPTH];
    let mut top = 0usize;
    let mut current = 0u32;
    hit_box(&nodes[0], ray.origin, inv, q.t_min, closest)?;
    loop {
        let n = &nodes[current as usize];
        if n.count > 0 {
            let first = n.left_or_first;
            if q.leaf((first..first + n.count).map(|s| (s, s - first)), &mut closest, &mut hit, observer) {
                return hit;
            }
        } else {
            observer.inner();
            let (a, b) = (current + 1, n.left_or_first);
            let ta = hit_box(&nodes[a as usize], ray.origin, inv, q.t_min, closest);
            let tb = hit_box(&nodes[b as usize], ray.origin, inv, q.t_min, closest);
            // Visit the nearer child first; the farther waits on the stack.
            if let Some(next) = nearer_child((a, ta), (b, tb), &mut stack, &mut top, observer) {
                current = next;
                continue;
            }
        }
        let Some(next) = pop(&stack, &mut top) else { return hit };
        current = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::BvhLayout;
    use crate::packed_scene::PackedScene;
    use crate::scene::builtin;
    use crate::settings::Accel;

    /// The BVH in every layout and the linear loop (single leaf) find the same closest primitive at the same
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

    /// Degenerate scenes: no primitive (every layout finds nothing) and one (the root a leaf:
    /// aila-laine's empty second child, the wide root's one leaf child) agree with binary.
    #[test]
    fn empty_and_single_primitive_scenes_in_every_layout() {
        let one = builtin::by_name("furnace").unwrap();
        let empty = crate::scene::Scene { spheres: Vec::new(), ..one.clone() };
        let ray = Ray { origin: V3::new(0.0f32, 0.0, 5.0), dir: V3::new(0.0, 0.0, -1.0) };
        for layout in [BvhLayout::Binary, BvhLayout::AilaLaine, BvhLayout::Wide] {
            let e = PackedScene::new(&empty, Accel::Bvh).with_bvh(layout, Default::default()).unwrap();
            assert_eq!(
                closest_hit(e.bvh_nodes(), &e.primitives, &ray, 1e-3, SphereHit::Stable, &mut ()),
                None
            );
            let s = PackedScene::new(&one, Accel::Bvh).with_bvh(layout, Default::default()).unwrap();
            let hit = closest_hit(s.bvh_nodes(), &s.primitives, &ray, 1e-3, SphereHit::Stable, &mut ());
            let want = super::hit_primitive(&s.primitives[0], &ray, 1e-3, f32::INFINITY, SphereHit::Stable);
            assert_eq!(hit.map(|h| (h.t, h.prim)), want.map(|t| (t, 0)), "{layout:?}");
            assert!(want.is_some());
        }
    }

    fn check_same_hits(name: &str) {
        for layout in [BvhLayout::Binary, BvhLayout::AilaLaine, BvhLayout::Wide] {
            check_layout(name, layout);
        }
    }

    fn check_layout(name: &str, layout: BvhLayout) {
        let scene = builtin::by_name(name).unwrap();
        let bvh = PackedScene::new(&scene, Accel::Bvh).with_bvh(layout, Default::default()).unwrap();
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
            let (nodes, lin) = (bvh.bvh_nodes(), linear.bvh_nodes());
            let a = closest_hit(nodes, &bvh.primitives, &ray, 1e-3f32, SphereHit::Stable, &mut ());
            let b = closest_hit(lin, &linear.primitives, &ray, 1e-3f32, SphereHit::Stable, &mut ());
            if let Some(a) = a {
                // Any-hit agrees: something before the closest hit's far side, nothing before it.
                assert!(occluded(nodes, &bvh.primitives, &ray, 1e-3, a.t * 1.001, u32::MAX), "ray {i}");
                assert!(!occluded(nodes, &bvh.primitives, &ray, 1e-3, a.t * 0.999, u32::MAX), "ray {i}");
                // Skipping the primitive hit, nothing lies before it.
                assert!(!occluded(nodes, &bvh.primitives, &ray, 1e-3, a.t, a.prim), "ray {i}");
            } else {
                assert!(!occluded(nodes, &bvh.primitives, &ray, 1e-3, f32::INFINITY, u32::MAX), "ray {i}");
            }
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert_eq!(a.t, b.t, "{layout:?} ray {i}");
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
                _ => panic!("{layout:?} ray {i}: BVH {a:?} vs linear {b:?}"),
            }
        }
        assert!(hits > 10_000, "most rays hit something ({hits})");
    }
}
