//! Closest-hit BVH traversal; twin of `shaders/shared/bvh.wgsl` (same stack, same child order).

use super::{ray::Ray, real::Real, sphere::hit_sphere, vec3::V3};
use crate::bvh::MAX_DEPTH;
use crate::layout::{BvhNode, SphereRecord};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<T> {
    pub t: T,
    /// Slot of the sphere in `PackedScene::spheres`.
    pub sphere: u32,
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

pub fn closest_hit<T: Real>(
    nodes: &[BvhNode],
    spheres: &[SphereRecord],
    ray: &Ray<T>,
    t_min: T,
) -> Option<Hit<T>> {
    let inv = safe_inverse(ray.dir);
    let mut closest = T::infinity();
    let mut hit = None;
    let mut stack = [0u32; MAX_DEPTH];
    let mut top = 0usize;
    let mut current = 0u32;
    hit_box(&nodes[0], ray.origin, inv, t_min, closest)?;
    loop {
        let n = &nodes[current as usize];
        if n.count > 0 {
            for slot in n.left_or_first..n.left_or_first + n.count {
                if let Some(t) = hit_sphere(&spheres[slot as usize], ray, t_min, closest) {
                    closest = t;
                    hit = Some(Hit { t, sphere: slot });
                }
            }
        } else {
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

    /// The BVH and the linear loop (single leaf) find the same closest sphere at the same
    /// distance for random rays through the final scene, from outside and inside spheres.
    #[test]
    fn bvh_and_linear_find_the_same_hits() {
        let scene = builtin::by_name("rtiow-final").unwrap();
        let bvh = PackedScene::new(&scene, Accel::Bvh);
        let linear = PackedScene::new(&scene, Accel::None);
        assert!(bvh.nodes.len() > 100 && linear.nodes.len() == 1);
        let mut s = crate::rng::Stream::new(11);
        let mut hits = 0;
        for i in 0..20_000 {
            let origin = if i % 4 == 0 {
                // Start at a random sphere's centre (inside it).
                V3::of(linear.spheres[(s.next_f32() * linear.spheres.len() as f32) as usize].center)
            } else {
                V3::new(s.range(-15.0, 15.0), s.range(0.0, 6.0), s.range(-15.0, 15.0))
            };
            let dir = V3::new(s.range(-1.0, 1.0), s.range(-1.0, 0.5), s.range(-1.0, 1.0)).normalize();
            let ray = Ray { origin, dir };
            let a = closest_hit(&bvh.nodes, &bvh.spheres, &ray, 1e-3f32);
            let b = closest_hit(&linear.nodes, &linear.spheres, &ray, 1e-3f32);
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert_eq!(a.t, b.t, "ray {i}");
                    assert_eq!(bvh.spheres[a.sphere as usize], linear.spheres[b.sphere as usize], "ray {i}");
                }
                (None, None) => {}
                _ => panic!("ray {i}: BVH {a:?} vs linear {b:?}"),
            }
        }
        assert!(hits > 10_000, "most rays hit something ({hits})");
    }
}
