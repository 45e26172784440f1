//! Bounding volume hierarchy over primitive boxes: binned SAH build on the CPU, flattened into
//! [`BvhNode`]s that the CPU reference (`cpu/bvh.rs`) and the GPU (`shaders/shared/bvh.wgsl`)
//! traverse with the same stack-based loop.

pub mod aila_laine;
pub mod collapse;
pub mod layout;
pub mod scene_bvh;
pub mod stack;
pub mod wide;

pub use layout::BvhLayout;
pub use scene_bvh::{BvhRef, BvhSummary, SceneBvh};

use crate::layout::BvhNode;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    pub fn union(self, o: Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area; 0 for an empty box.
    pub fn area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
}

/// A flattened BVH and the order in which primitives must be stored so leaves index them.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    /// `order[i]` is the original index of the primitive stored at slot `i`.
    pub order: Vec<u32>,
}

/// Leaves stop splitting at this many primitives whatever the SAH says.
const MAX_LEAF: usize = 4;
const BINS: usize = 16;
/// SAH cost of one traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;
/// The traversal stack depth in `cpu/bvh.rs` and `bvh.wgsl`; builds deeper than this are refused.
pub const MAX_DEPTH: usize = 64;

impl Bvh {
    /// A single leaf over all primitives: the seeds' linear loop (`--accel none`).
    pub fn single_leaf(boxes: &[Aabb]) -> Bvh {
        let bounds = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        let bounds = if boxes.is_empty() { Aabb { min: Vec3::ZERO, max: Vec3::ZERO } } else { bounds };
        Bvh { nodes: vec![node(bounds, 0, boxes.len() as u32)], order: (0..boxes.len() as u32).collect() }
    }

    /// Binned SAH build (16 bins per axis over centroid bounds).
    pub fn build(boxes: &[Aabb]) -> Bvh {
        if boxes.len() <= 1 {
            return Bvh::single_leaf(boxes);
        }
        let mut builder = Builder {
            boxes,
            centroids: boxes.iter().map(Aabb::centroid).collect(),
            order: (0..boxes.len() as u32).collect(),
            nodes: Vec::with_capacity(2 * boxes.len()),
        };
        builder.split(0, boxes.len(), 1);
        Bvh { nodes: builder.nodes, order: builder.order }
    }

    /// The deepest root-to-leaf path, in nodes.
    pub fn depth(&self) -> usize {
        fn go(nodes: &[BvhNode], i: usize) -> usize {
            let n = &nodes[i];
            if n.count > 0 {
                1
            } else {
                1 + go(nodes, i + 1).max(go(nodes, n.left_or_first as usize))
            }
        }
        go(&self.nodes, 0)
    }
}

fn node(b: Aabb, left_or_first: u32, count: u32) -> BvhNode {
    BvhNode { min: b.min.to_array(), left_or_first, max: b.max.to_array(), count }
}

struct Builder<'a> {
    boxes: &'a [Aabb],
    centroids: Vec<Vec3>,
    order: Vec<u32>,
    nodes: Vec<BvhNode>,
}

impl Builder<'_> {
    fn bounds(&self, start: usize, end: usize) -> (Aabb, Aabb) {
        let mut b = Aabb::EMPTY;
        let mut c = Aabb::EMPTY;
        for &i in &self.order[start..end] {
            b = b.union(self.boxes[i as usize]);
            c = c.grow(self.centroids[i as usize]);
        }
        (b, c)
    }

    /// Builds the subtree over `order[start..end]` at the end of `nodes`; returns its index.
    fn split(&mut self, start: usize, end: usize, depth: usize) -> u32 {
        let index = self.nodes.len();
        let (bounds, cbounds) = self.bounds(start, end);
        let count = end - start;
        self.nodes.push(node(bounds, start as u32, count as u32));
        let extent = cbounds.max - cbounds.min;
        // Past the stack depth every method supports, stop splitting (a deep leaf beats a
        // traversal that overflows its stack).
        if count <= 1 || depth + 1 >= MAX_DEPTH || extent.max_element() <= 0.0 {
            return index as u32;
        }
        let Some((axis, bin_split, cost)) = self.best_split(start, end, cbounds) else {
            return index as u32;
        };
        let leaf_cost = count as f32;
        if count <= MAX_LEAF && cost >= leaf_cost {
            return index as u32;
        }
        let lo = cbounds.min[axis];
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - lo) * scale) as usize).min(BINS - 1);
        let centroids = &self.centroids;
        let mid =
            start + partition(&mut self.order[start..end], |&i| bin_of(centroids[i as usize]) < bin_split);
        if mid == start || mid == end {
            return index as u32;
        }
        self.split(start, mid, depth + 1);
        let right = self.split(mid, end, depth + 1);
        self.nodes[index].left_or_first = right;
        self.nodes[index].count = 0;
        index as u32
    }

    /// The cheapest (axis, first bin of the right side, SAH cost) over all binned planes.
    fn best_split(&self, start: usize, end: usize, cbounds: Aabb) -> Option<(usize, usize, f32)> {
        let parent_area = self.bounds(start, end).0.area().max(f32::MIN_POSITIVE);
        let mut best: Option<(usize, usize, f32)> = None;
        for axis in 0..3 {
            let lo = cbounds.min[axis];
            let extent = cbounds.max[axis] - lo;
            if extent <= 0.0 {
                continue;
            }
            let scale = BINS as f32 / extent;
            let mut bins = [(Aabb::EMPTY, 0usize); BINS];
            for &i in &self.order[start..end] {
                let b = (((self.centroids[i as usize][axis] - lo) * scale) as usize).min(BINS - 1);
                bins[b].0 = bins[b].0.union(self.boxes[i as usize]);
                bins[b].1 += 1;
            }
            // Sweep from the right so each plane's right side is known, then from the left.
            let mut right_area = [0.0f32; BINS];
            let mut right_count = [0usize; BINS];
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for b in (1..BINS).rev() {
                acc = acc.union(bins[b].0);
                n += bins[b].1;
                right_area[b] = acc.area();
                right_count[b] = n;
            }
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for b in 1..BINS {
                acc = acc.union(bins[b - 1].0);
                n += bins[b - 1].1;
                if n == 0 || right_count[b] == 0 {
                    continue;
                }
                let cost = TRAVERSAL_COST
                    + (acc.area() * n as f32 + right_area[b] * right_count[b] as f32) / parent_area;
                if best.is_none_or(|(_, _, c)| cost < c) {
                    best = Some((axis, b, cost));
                }
            }
        }
        best
    }
}

/// Moves the elements for which `pred` holds to the front; returns how many there are.
fn partition<T>(v: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut first = 0;
    for i in 0..v.len() {
        if pred(&v[i]) {
            v.swap(first, i);
            first += 1;
        }
    }
    first
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random_boxes(n: usize) -> Vec<Aabb> {
        let mut s = crate::rng::Stream::new(42);
        (0..n)
            .map(|_| {
                let c = Vec3::new(s.range(-50.0, 50.0), s.range(-5.0, 5.0), s.range(-50.0, 50.0));
                let r = s.range(0.1, 2.0);
                Aabb { min: c - r, max: c + r }
            })
            .collect()
    }

    /// Every primitive sits in exactly one leaf, and every node's box contains its children.
    fn check(bvh: &Bvh, boxes: &[Aabb]) {
        let mut seen = vec![0; boxes.len()];
        fn walk(bvh: &Bvh, boxes: &[Aabb], i: usize, seen: &mut [u32]) -> Aabb {
            let n = bvh.nodes[i];
            let b = Aabb { min: Vec3::from(n.min), max: Vec3::from(n.max) };
            let inner = if n.count > 0 {
                let range = n.left_or_first as usize..(n.left_or_first + n.count) as usize;
                let mut u = Aabb::EMPTY;
                for slot in range {
                    let prim = bvh.order[slot] as usize;
                    seen[prim] += 1;
                    u = u.union(boxes[prim]);
                }
                u
            } else {
                walk(bvh, boxes, i + 1, seen).union(walk(bvh, boxes, n.left_or_first as usize, seen))
            };
            assert!(b.min.cmple(inner.min).all() && b.max.cmpge(inner.max).all());
            b
        }
        walk(bvh, boxes, 0, &mut seen);
        assert!(seen.iter().all(|&k| k == 1), "each primitive in exactly one leaf");
    }

    #[test]
    fn sah_build_is_a_valid_partition() {
        let boxes = random_boxes(1000);
        let bvh = Bvh::build(&boxes);
        check(&bvh, &boxes);
        assert!(bvh.nodes.len() > 100, "a real hierarchy, not one leaf");
        assert!(bvh.depth() < 40, "depth {}", bvh.depth());
    }

    #[test]
    fn identical_boxes_stop_splitting_without_recursing_forever() {
        let b = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let boxes = vec![b; 100];
        let bvh = Bvh::build(&boxes);
        check(&bvh, &boxes);
        assert_eq!(bvh.nodes.len(), 1);
    }

    #[test]
    fn single_leaf_holds_everything_in_order() {
        let boxes = random_boxes(10);
        let bvh = Bvh::single_leaf(&boxes);
        check(&bvh, &boxes);
        assert_eq!(bvh.nodes[0].count, 10);
        assert_eq!(bvh.order, (0..10).collect::<Vec<_>>());
    }
}
