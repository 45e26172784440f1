//! The Aila–Laine layout: the binary build with both child boxes stored in the parent (64-byte
//! nodes), so one fetch tests both children and leaves are ranges named in their parent, never
//! fetched as nodes. Traversed by `cpu/bvh_aila_laine.rs` and `shaders/shared/bvh_aila_laine.wgsl`.

use crate::layout::BvhNode;
use bytemuck::{Pod, Zeroable};

/// A child's `count` word with this bit set names a leaf of `count & !LEAF` primitives from
/// `first`; without it (0), `first` is an inner node's index. A leaf may hold no primitive:
/// the root's second child when the whole scene is one leaf.
pub const LEAF: u32 = 0x8000_0000;

/// WGSL: read as four `vec4<u32>` in `bvh_aila_laine.wgsl` (`al_child`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AilaLaineNode {
    pub left: Child,
    pub right: Child,
}

/// One child: its box and what it is.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Child {
    pub min: [f32; 3],
    /// An inner node's index, or a leaf's first primitive slot.
    pub first: u32,
    pub max: [f32; 3],
    /// 0 for an inner node, `LEAF | count` for a leaf.
    pub count: u32,
}

impl Child {
    pub fn is_leaf(&self) -> bool {
        self.count != 0
    }

    pub fn primitives(&self) -> u32 {
        self.count & !LEAF
    }
}

/// The binary BVH `nodes` (`bvh::Bvh`'s: left child next, right at `left_or_first`) in the
/// Aila–Laine layout: one node per binary inner node, in the same depth-first order, the root
/// first. A binary tree that is one leaf becomes a root whose left child is that leaf and whose
/// right is an empty one.
pub fn from_binary(nodes: &[BvhNode]) -> Vec<AilaLaineNode> {
    if nodes.is_empty() {
        return Vec::new();
    }
    // Index of each binary inner node in the output (depth-first order is kept).
    let mut index = vec![u32::MAX; nodes.len()];
    let mut next = 0u32;
    for (i, n) in nodes.iter().enumerate() {
        if n.count == 0 {
            index[i] = next;
            next += 1;
        }
    }
    let child = |i: usize| {
        let n = &nodes[i];
        let (first, count) = if n.count > 0 { (n.left_or_first, LEAF | n.count) } else { (index[i], 0) };
        Child { min: n.min, first, max: n.max, count }
    };
    if nodes[0].count > 0 || nodes.len() == 1 {
        let leaf = child(0);
        return vec![AilaLaineNode { left: leaf, right: Child { first: 0, count: LEAF, ..leaf } }];
    }
    let mut out = Vec::with_capacity(next as usize);
    for (i, n) in nodes.iter().enumerate() {
        if n.count == 0 {
            out.push(AilaLaineNode { left: child(i + 1), right: child(n.left_or_first as usize) });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{Aabb, Bvh};
    use glam::Vec3;

    /// Every binary node's box and leaf range reappear under the same parent.
    #[test]
    fn children_keep_the_binary_boxes_and_ranges() {
        let mut s = crate::rng::Stream::new(5);
        let boxes: Vec<Aabb> = (0..300)
            .map(|_| {
                let c = Vec3::new(s.range(-9.0, 9.0), s.range(-9.0, 9.0), s.range(-9.0, 9.0));
                Aabb { min: c - 0.3, max: c + 0.3 }
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let al = from_binary(&bvh.nodes);
        let inner = bvh.nodes.iter().filter(|n| n.count == 0).count();
        assert_eq!(al.len(), inner);
        let mut leaves = 0;
        for a in &al {
            for c in [a.left, a.right] {
                if c.is_leaf() {
                    leaves += c.primitives();
                } else {
                    assert!((c.first as usize) < al.len());
                }
            }
        }
        assert_eq!(leaves as usize, boxes.len(), "each primitive in one leaf");
        // One leaf: the root holds it and an empty second child.
        let one = from_binary(&Bvh::single_leaf(&boxes[..3]).nodes);
        assert_eq!(
            (one[0].left.primitives(), one[0].right.primitives(), one[0].right.is_leaf()),
            (3, 0, true)
        );
    }
}
