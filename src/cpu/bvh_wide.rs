//! Closest-hit and any-hit traversal of the compressed 8-wide layout (`bvh::wide`); twin of
//! `shaders/shared/bvh_wide.wgsl`. Ylitie et al.'s loop as tinybvh's `traverse_cwbvh.cl` has it:
//! a stack of node groups (the first inner child's index, and a mask of the hit inner children
//! over the parent's `imask`), the nearest child taken by the highest bit of the mask, whose
//! bits are the slots in the ray's octant order; the hit leaf children's primitives tested
//! in slot order. A child's box is dequantized to f32 planes (`wide::plane`) and met with the
//! binary layout's slab test, so a ray entering a binary node's box enters the larger wide one.

use super::bvh::{safe_inverse, Hit, Query};
use super::observe::PathObserver;
use super::real::Real;
use super::vec3::V3;
use crate::bvh::wide::{WideNode, MAX_DEPTH};

/// The ray's octant (bit 2: x < 0, bit 1: y < 0, bit 0: z < 0) flipped: the slot order
/// `slot ^ octant_inverse` visits first the slot the builder gave the child nearest that way.
#[inline(always)]
pub fn octant_inverse<T: Real>(d: V3<T>) -> u32 {
    let neg = |c: T, bit: u32| if c < T::zero() { bit } else { 0 };
    7 - (neg(d.x, 4) | neg(d.y, 2) | neg(d.z, 1))
}

#[inline(always)]
pub fn traverse<T: Real>(
    nodes: &[WideNode],
    q: &Query<T>,
    observer: &mut impl PathObserver,
) -> Option<Hit<T>> {
    let ray = q.ray;
    let inv = safe_inverse(ray.dir);
    let octinv = octant_inverse(ray.dir);
    let mut closest = q.t_max;
    let mut hit = None;
    let mut stack = [(0u32, 0u32); MAX_DEPTH];
    let mut top = 0usize;
    // (first inner child, hit children in bits 24..31 | the parent's imask): the root alone.
    let mut group = (0u32, 0x8000_0000u32);
    loop {
        if group.1 > 0x00ff_ffff {
            let bit = 31 - group.1.leading_zeros();
            let imask = group.1 & 0xff;
            let base = group.0;
            group.1 &= !(1 << bit);
            if group.1 > 0x00ff_ffff {
                stack[top] = group;
                top += 1;
                observer.stack(top);
            }
            let slot = (bit - 24) ^ octinv;
            let n = &nodes[(base + (imask & ((1 << slot) - 1)).count_ones()) as usize];
            observer.inner();
            let hits = hit_children(n, ray.origin, inv, (q.t_min, closest), octinv);
            group = (n.child_base, (hits & 0xff00_0000) | n.imask() as u32);
            let mut prims = hits & 0x00ff_ffff;
            if prims != 0 {
                let mut tested = 0u32;
                while prims != 0 {
                    let k = prims.trailing_zeros();
                    prims &= prims - 1;
                    let slot = n.prim_base + k;
                    if slot == q.skip {
                        continue;
                    }
                    tested |= 1 << k;
                    if let Some(t) = q.hit(slot, closest) {
                        closest = t;
                        hit = Some(Hit { t, prim: slot });
                        if q.any_hit {
                            observer.leaf(tested);
                            return hit;
                        }
                    }
                }
                observer.leaf(tested);
            }
        }
        if group.1 <= 0x00ff_ffff {
            if top == 0 {
                return hit;
            }
            top -= 1;
            group = stack[top];
        }
    }
}

/// The node's children the ray enters in (t_min, t_max): an inner child as bit
/// 24 + (slot ^ octinv), a leaf as one bit per primitive from its offset. The eight slots side
/// by side, so the compiler can test them together: each slot's box and slab test are
/// `wide::plane` and `hit_bounds` operation for operation (the same roundings, the same order of
/// min and max), with the scales computed once per node.
#[inline(always)]
fn hit_children<T: Real>(n: &WideNode, o: V3<T>, inv: V3<T>, (t_min, t_max): (T, T), octinv: u32) -> u32 {
    let (o, inv) = ([o.x, o.y, o.z], [inv.x, inv.y, inv.z]);
    let mut enter = [[T::zero(); 8]; 3];
    let mut leave = [[T::zero(); 8]; 3];
    for a in 0..3 {
        let (p, scale) = (n.p[a], f32::from_bits((n.e_imask[a] as u32) << 23));
        for slot in 0..8 {
            let t1 = (T::of(p + n.qlo[a][slot] as f32 * scale) - o[a]) * inv[a];
            let t2 = (T::of(p + n.qhi[a][slot] as f32 * scale) - o[a]) * inv[a];
            enter[a][slot] = t1.min(t2);
            leave[a][slot] = t1.max(t2);
        }
    }
    let mut hits = 0u32;
    for slot in 0..8 {
        let near = enter[0][slot].max(enter[1][slot]).max(enter[2][slot]).max(t_min);
        let far = leave[0][slot].min(leave[1][slot]).min(leave[2][slot]).min(t_max);
        let meta = n.meta[slot] as u32;
        if meta != 0 && near <= far {
            let shift = if n.imask() >> slot & 1 == 1 { 24 + (slot as u32 ^ octinv) } else { meta & 31 };
            hits |= (meta >> 5) << shift;
        }
    }
    hits
}
