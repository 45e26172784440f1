//! The compressed 8-wide layout (Ylitie, Karras & Laine 2017, "CWBVH"): the binary build
//! collapsed into nodes of up to 8 children (`collapse.rs`: greedily, or SAH-optimal), each child's box quantized to 8 bits per
//! bound against the node's frame (origin `p`, power-of-two scales `2^e`), inner children stored
//! contiguously (child i at `child_base` + the inner children in slots below i), leaves of at
//! most 3 primitives stored contiguously from `prim_base`, children placed in slots by octant so
//! that a ray visits them nearly front to back. Quantization is conservative: the box a
//! traversal dequantizes (`plane`, in f32) never excludes any part of the child's box. Traversed
//! by `cpu/bvh_wide.rs` and `shaders/shared/bvh_wide.wgsl`.

use super::collapse::{Collapse, Part, Sub, Tree};
use super::Aabb;
use crate::layout::BvhNode;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use std::collections::VecDeque;

/// Primitives in one leaf child at most (the meta byte's unary count has 3 bits).
pub const MAX_LEAF: u32 = 3;
/// The wide traversal's stack of node groups; builds deeper than this are refused.
pub const MAX_DEPTH: usize = 64;

/// WGSL: read as five `vec4<u32>` in `bvh_wide.wgsl` (`wide_node`); Ylitie et al.'s 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WideNode {
    /// The frame's origin: the node's box's low corner.
    pub p: [f32; 3],
    /// Per axis the scale's biased exponent (scale = 2^(e − 127), an f32's exponent bits),
    /// then `imask`: bit i set when slot i holds an inner child.
    pub e_imask: [u8; 4],
    /// Index of the first inner child; the others follow in slot order.
    pub child_base: u32,
    /// Slot of the first primitive of the leaf children; theirs follow in slot order.
    pub prim_base: u32,
    /// Per slot: 0 empty; an inner child `0b001_00000 | (24 + slot)`; a leaf
    /// `unary(count) << 5 | offset of its first primitive from prim_base`.
    pub meta: [u8; 8],
    /// Quantized low bounds, per axis per slot.
    pub qlo: [[u8; 8]; 3],
    /// Quantized high bounds, per axis per slot.
    pub qhi: [[u8; 8]; 3],
}

impl WideNode {
    pub fn imask(&self) -> u8 {
        self.e_imask[3]
    }

    /// The child in `slot`'s box as the traversal dequantizes it.
    pub fn child_box(&self, slot: usize) -> Aabb {
        let f = |a: usize, q: u8| plane(self.p[a], q, self.e_imask[a]);
        Aabb {
            min: Vec3::new(f(0, self.qlo[0][slot]), f(1, self.qlo[1][slot]), f(2, self.qlo[2][slot])),
            max: Vec3::new(f(0, self.qhi[0][slot]), f(1, self.qhi[1][slot]), f(2, self.qhi[2][slot])),
        }
    }
}

/// A dequantized bound: `p + q · 2^(e − 127)` in f32, as every traversal computes it (the
/// product is exact, so a fused multiply-add rounds the same).
#[inline(always)]
pub fn plane(p: f32, q: u8, e: u8) -> f32 {
    p + q as f32 * f32::from_bits((e as u32) << 23)
}

/// The wide BVH and the order its leaves need the primitives in.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    pub nodes: Vec<WideNode>,
    /// `order[i]`: the slot (in the binary build's order) of the primitive stored at slot `i`.
    pub order: Vec<u32>,
    /// Levels of wide nodes from the root to the deepest.
    pub depth: u32,
}

/// The wide BVH over the binary build `binary` (`bvh::Bvh`'s nodes) whose primitives, in its
/// order, have boxes `boxes`, collapsed by `collapse`. Errors for a tree deeper than the
/// traversal's stack and for a box that no f32 frame can quantize (an infinite extent).
pub fn build(binary: &[BvhNode], boxes: &[Aabb], collapse: Collapse) -> Result<WideBvh, String> {
    let b = Tree::new(binary, boxes, collapse);
    let mut out =
        WideBvh { nodes: vec![WideNode::default()], order: Vec::with_capacity(boxes.len()), depth: 1 };
    if binary.is_empty() {
        return Ok(out);
    }
    let mut queue = VecDeque::from([(b.sub(0), 0usize, 1u32)]);
    while let Some((sub, index, depth)) = queue.pop_front() {
        out.depth = out.depth.max(depth);
        if depth as usize > MAX_DEPTH {
            return Err(format!(
                "the wide BVH is deeper than its traversal's stack ({MAX_DEPTH} levels): the scene's \
                 primitives are too unevenly spread for --bvh wide; use --bvh binary"
            ));
        }
        let kids = b.collapse(&sub);
        let slots = assign_slots(&kids, sub.bounds.centroid());
        let mut node = frame(sub.bounds)?;
        node.child_base = out.nodes.len() as u32;
        node.prim_base = out.order.len() as u32;
        let mut by_slot: Vec<(usize, &Sub)> = slots.iter().copied().zip(&kids).collect();
        by_slot.sort_by_key(|&(slot, _)| slot);
        for (slot, kid) in by_slot {
            quantize(&mut node, slot, kid.bounds);
            match kid.part {
                Part::Range(first, count) if count <= MAX_LEAF => {
                    let offset = out.order.len() as u32 - node.prim_base;
                    node.meta[slot] = (((1u32 << count) - 1) << 5 | offset) as u8;
                    out.order.extend(first..first + count);
                }
                _ => {
                    node.meta[slot] = (1 << 5 | (24 + slot)) as u8;
                    node.e_imask[3] |= 1 << slot;
                    queue.push_back((*kid, out.nodes.len(), depth + 1));
                    out.nodes.push(WideNode::default());
                }
            }
        }
        out.nodes[index] = node;
    }
    Ok(out)
}

/// Slot of each child: the child a ray of octant s (bit 2: x < 0, bit 1: y < 0, bit 0: z < 0)
/// meets first goes in slot s where it can, so the traversal's octant order is front to back.
/// Greedy over the (child, slot) pairs from the cheapest (Ylitie et al. use an auction).
fn assign_slots(kids: &[Sub], center: Vec3) -> Vec<usize> {
    let dir = |s: usize| {
        let sign = |bit: usize| if s & bit != 0 { -1.0 } else { 1.0 };
        Vec3::new(sign(4), sign(2), sign(1))
    };
    let mut pairs: Vec<(f32, usize, usize)> = Vec::with_capacity(kids.len() * 8);
    for (k, kid) in kids.iter().enumerate() {
        for s in 0..8 {
            pairs.push(((kid.bounds.centroid() - center).dot(dir(s)), k, s));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut slot_of, mut taken) = (vec![usize::MAX; kids.len()], [false; 8]);
    for (_, k, s) in pairs {
        if slot_of[k] == usize::MAX && !taken[s] {
            slot_of[k] = s;
            taken[s] = true;
        }
    }
    slot_of
}

/// A node whose frame covers `b`: origin at its low corner, and per axis the smallest scale
/// 2^e with which 255 steps reach its high corner (as `plane` computes it).
fn frame(b: Aabb) -> Result<WideNode, String> {
    let mut node = WideNode { p: b.min.to_array(), ..Default::default() };
    for a in 0..3 {
        let extent = b.max[a] - b.min[a];
        if !extent.is_finite() {
            return Err(format!(
                "a BVH node's box spans {extent} on axis {a} (from {} to {}): --bvh wide cannot \
                 quantize it; use --bvh binary",
                b.min[a], b.max[a]
            ));
        }
        let mut e = if extent > 0.0 { ((extent / 255.0).log2().ceil() as i32 + 127).max(1) } else { 1 };
        while e < 254 && plane(b.min[a], 255, e as u8) < b.max[a] {
            e += 1;
        }
        if plane(b.min[a], 255, e as u8) < b.max[a] {
            return Err(format!("a BVH node's box on axis {a} (from {} to {}) is too large for --bvh wide's frames; use --bvh binary", b.min[a], b.max[a]));
        }
        // Never coarser than needed: one step down must not reach (log2 rounding).
        while e > 1 && plane(b.min[a], 255, (e - 1) as u8) >= b.max[a] {
            e -= 1;
        }
        node.e_imask[a] = e as u8;
    }
    Ok(node)
}

/// Stores `child`'s box in `slot`, rounded outwards: each bound moved a step further out until
/// `plane` of it contains the box.
fn quantize(node: &mut WideNode, slot: usize, child: Aabb) {
    for a in 0..3 {
        let (p, e) = (node.p[a], node.e_imask[a]);
        let step = f32::from_bits((e as u32) << 23);
        let mut lo = ((child.min[a] - p) / step).floor().clamp(0.0, 255.0) as u8;
        while lo > 0 && plane(p, lo, e) > child.min[a] {
            lo -= 1;
        }
        let mut hi = ((child.max[a] - p) / step).ceil().clamp(0.0, 255.0) as u8;
        while hi < 255 && plane(p, hi, e) < child.max[a] {
            hi += 1;
        }
        node.qlo[a][slot] = lo;
        node.qhi[a][slot] = hi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::Bvh;

    /// Boxes of very different sizes and places, so frames need every scale.
    fn boxes(n: usize, seed: u32) -> Vec<Aabb> {
        let mut s = crate::rng::Stream::new(seed);
        (0..n)
            .map(|i| {
                let spread = [1e-3, 1.0, 1e4][i % 3];
                let c = Vec3::new(s.range(-1.0, 1.0), s.range(-1.0, 1.0), s.range(-1.0, 1.0)) * spread + 7.25;
                let r = Vec3::new(s.range(0.0, 1.0), s.range(0.0, 0.01), s.range(0.0, 2.0)) * spread;
                Aabb { min: c - r, max: c + r }
            })
            .collect()
    }

    /// No child box shrinks: every primitive's box lies inside the dequantized box of each
    /// wide node's child on its way from the root, and each primitive is in one leaf.
    #[test]
    fn quantized_child_boxes_never_shrink() {
        for (n, seed, collapse) in [
            (2000, 1, Collapse::Greedy),
            (2000, 1, Collapse::Sah),
            (7, 2, Collapse::Greedy),
            (7, 2, Collapse::Sah),
            (1, 3, Collapse::Sah),
        ] {
            let unordered = boxes(n, seed);
            let bvh = Bvh::build(&unordered);
            // In the binary build's order, as `PackedScene` stores the primitives.
            let b: Vec<Aabb> = bvh.order.iter().map(|&i| unordered[i as usize]).collect();
            let wide = build(&bvh.nodes, &b, collapse).unwrap();
            let mut sorted = wide.order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "a permutation");
            // Walk: (node, the primitive boxes it must contain).
            let mut seen = 0;
            let mut stack = vec![0usize];
            while let Some(i) = stack.pop() {
                let node = &wide.nodes[i];
                let mut inner = 0;
                for slot in 0..8 {
                    let meta = node.meta[slot];
                    if meta == 0 {
                        continue;
                    }
                    let bx = node.child_box(slot);
                    let inside = |p: &Aabb| bx.min.cmple(p.min).all() && bx.max.cmpge(p.max).all();
                    if node.imask() >> slot & 1 == 1 {
                        let child = node.child_base as usize + inner;
                        inner += 1;
                        // Every primitive under the child lies in its box.
                        let mut under = vec![child];
                        while let Some(c) = under.pop() {
                            let cn = &wide.nodes[c];
                            let (leaf_prims, inner_kids) = prims_and_children(cn);
                            for p in leaf_prims {
                                assert!(inside(&b[wide.order[p as usize] as usize]), "node {i} slot {slot}");
                            }
                            under.extend(inner_kids);
                        }
                        stack.push(child);
                    } else {
                        let (count, offset) = ((meta >> 5).count_ones(), (meta & 31) as u32);
                        assert!((1..=MAX_LEAF).contains(&count) && offset + count <= 24);
                        for k in 0..count {
                            let slot_prim = node.prim_base + offset + k;
                            assert!(inside(&b[wide.order[slot_prim as usize] as usize]));
                            seen += 1;
                        }
                    }
                }
            }
            assert_eq!(seen, n, "each primitive in one leaf");
        }
    }

    /// A node's leaf primitives (slots) and inner children (indices).
    fn prims_and_children(n: &WideNode) -> (Vec<u32>, Vec<usize>) {
        let (mut prims, mut kids) = (Vec::new(), Vec::new());
        for slot in 0..8 {
            let meta = n.meta[slot];
            if meta == 0 {
                continue;
            }
            if n.imask() >> slot & 1 == 1 {
                kids.push(
                    n.child_base as usize + (n.imask() as u32 & ((1 << slot) - 1)).count_ones() as usize,
                );
            } else {
                let offset = (meta & 31) as u32;
                prims.extend((0..(meta >> 5).count_ones()).map(|k| n.prim_base + offset + k));
            }
        }
        (prims, kids)
    }

    /// Big leaves (identical boxes) are cut into leaves of 3; an infinite box is refused with
    /// a message naming the layout to use instead.
    #[test]
    fn big_leaves_split_and_infinite_boxes_are_refused() {
        let b = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 50];
        let bvh = Bvh::build(&b);
        assert_eq!(bvh.nodes.len(), 1);
        let wide = build(&bvh.nodes, &b, Collapse::Greedy).unwrap();
        assert!(wide.nodes.len() > 1 && wide.order.len() == 50);
        let huge = vec![
            Aabb { min: Vec3::splat(-3e38), max: Vec3::splat(3e38) },
            Aabb { min: Vec3::ZERO, max: Vec3::ONE },
        ];
        let err = build(&Bvh::build(&huge).nodes, &huge, Collapse::Greedy).unwrap_err();
        assert!(err.contains("--bvh binary"), "{err}");
    }
}
