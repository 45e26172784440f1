//! Closest-hit and any-hit traversal of the Aila–Laine layout (`bvh::aila_laine`); twin of
//! `shaders/shared/bvh_aila_laine.wgsl`. The binary loop's steps (nearer child first, the
//! farther on the stack), but a child is tested from its parent's node, and the stack holds
//! child references (first, count), so a leaf is never fetched as a node.

use super::bvh::{hit_bounds, nearer_child, pop, safe_inverse, Hit, Query};
use super::observe::PathObserver;
use super::real::Real;
use crate::bvh::aila_laine::{AilaLaineNode, LEAF};
use crate::bvh::MAX_DEPTH;

#[inline(always)]
pub fn traverse<T: Real>(
    nodes: &[AilaLaineNode],
    q: &Query<T>,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    let ray = q.ray;
    let inv = safe_inverse(ray.dir);
    let mut closest = q.t_max;
    let mut hit = None;
    let mut stack = [(0u32, 0u32); MAX_DEPTH];
    let mut top = 0usize;
    // (inner node index, 0) or (first primitive slot, LEAF | count): the root first.
    let mut current = (0u32, 0u32);
    if nodes.is_empty() {
        return None;
    }
    loop {
        let (first, count) = current;
        if count != 0 {
            let slots = (first..first + (count & !LEAF)).map(|s| (s, s - first));
            if q.leaf(slots, &mut closest, &mut hit, observer) {
                return hit;
            }
        } else {
            observer.inner();
            let n = &nodes[first as usize];
            let (a, b) = ((n.left.first, n.left.count), (n.right.first, n.right.count));
            let ta = hit_bounds(n.left.min, n.left.max, ray.origin, inv, q.t_min, closest);
            let tb = hit_bounds(n.right.min, n.right.max, ray.origin, inv, q.t_min, closest);
            if let Some(next) = nearer_child((a, ta), (b, tb), &mut stack, &mut top, observer) {
                current = next;
                continue;
            }
        }
        let Some(next) = pop(&stack, &mut top) else { return hit };
        current = next;
    }
}
