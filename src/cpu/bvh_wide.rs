//! Closest-hit and any-hit traversal of the compressed 8-wide layout (`bvh::wide`); twin of
//! `shaders/shared/bvh_wide.wgsl`. Ylitie et al.'s loop as tinybvh's `traverse_cwbvh.cl` has it:
//! a stack of node groups (the first inner child's index, and a mask of the hit inner children
//! over the parent's `imask`), the nearest child taken by the highest bit of the mask, whose
//! bits are the slots in the ray's octant order; the hit leaf children's primitives tested
//! in slot order. A child's box is dequantized to f32 planes (`wide::plane`) and met with the
//! binary layout's slab test, so a ray entering a binary node's box enters the larger wide one.
//! Children are visited in the octant order, not sorted by distance: the visits stay the WGSL
//! loop's step for step, which the `--instrument` counts rely on. What the CPU adds: the eight
//! children tested as SoA lanes, and prefetches of the hit children and leaf primitives.

use super::bvh::{pop, safe_inverse, Hit, Query};
use super::observe::PathObserver;
use super::real::Real;
use super::vec3::V3;
use crate::bvh::wide::{WideNode, MAX_DEPTH};
use crate::layout::PrimitiveRecord;

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
    let slabs = Slabs::new(ray.origin, inv);
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
            let hits = hit_children(n, &slabs, (q.t_min, closest), octinv, (nodes, q.prims));
            group = (n.child_base, (hits & 0xff00_0000) | n.imask() as u32);
            let mut prims = hits & 0x00ff_ffff;
            if prims != 0 {
                let slots = std::iter::from_fn(|| {
                    (prims != 0).then(|| {
                        let k = prims.trailing_zeros();
                        prims &= prims - 1;
                        (n.prim_base + k, k)
                    })
                });
                if q.leaf(slots, &mut closest, &mut hit, observer) {
                    return hit;
                }
            }
        }
        if group.1 <= 0x00ff_ffff {
            let Some(next) = pop(&stack, &mut top) else { return hit };
            group = next;
        }
    }
}

/// The node's children the ray enters in (t_min, t_max): an inner child as bit
/// 24 + (slot ^ octinv), a leaf as one bit per primitive from its offset.
///
/// The eight slots are tested together as arrays of eight lanes (SoA), which LLVM vectorizes
/// on stable Rust (std::simd is nightly-only): per axis, the bound the ray meets first is picked
/// once per ray (`Slabs::near_lo`), so a slot's entry and exit need no min/max of the two
/// planes, and no lane branches. Each plane is `wide::plane` and each distance `hit_bounds`'s
/// operation for operation (the same roundings; their max/min are the same values, the
/// operands never being NaN: finite planes and origin, and `safe_inverse` is finite and
/// nonzero), so a ray entering a binary node's box enters the wider wide one.
#[inline(always)]
fn hit_children<T: Real>(
    n: &WideNode,
    r: &Slabs<T>,
    (t_min, t_max): (T, T),
    octinv: u32,
    (nodes, prims): (&[WideNode], &[PrimitiveRecord]),
) -> u32 {
    let mut near = [t_min; 8];
    let mut far = [t_max; 8];
    for a in 0..3 {
        let (p, scale) = (n.p[a], f32::from_bits((n.e_imask[a] as u32) << 23));
        let (qn, qf) = if r.near_lo[a] { (&n.qlo[a], &n.qhi[a]) } else { (&n.qhi[a], &n.qlo[a]) };
        let (o, inv) = (r.o[a], r.inv[a]);
        for slot in 0..8 {
            let tn = (T::of(p + qn[slot] as f32 * scale) - o) * inv;
            let tf = (T::of(p + qf[slot] as f32 * scale) - o) * inv;
            near[slot] = if tn > near[slot] { tn } else { near[slot] };
            far[slot] = if tf < far[slot] { tf } else { far[slot] };
        }
    }
    let mut entered = 0u32;
    for slot in 0..8 {
        entered |= ((near[slot] <= far[slot]) as u32 & (n.meta[slot] != 0) as u32) << slot;
    }
    // An inner child's meta holds 24 + slot in its low bits: xor with octinv gives its bit.
    // Each entered child is prefetched too (the node of an inner child, the primitives of a
    // leaf), picked without a branch, so that the cache misses of a large scene overlap.
    let imask = n.imask() as u32;
    let mut hits = 0u32;
    while entered != 0 {
        let slot = entered.trailing_zeros();
        entered &= entered - 1;
        let meta = n.meta[slot as usize] as u32;
        let is_inner = imask >> slot & 1;
        hits |= (meta >> 5) << ((meta & 31) ^ (octinv & 0u32.wrapping_sub(is_inner)));
        let child =
            nodes.as_ptr().wrapping_add((n.child_base + (imask & ((1 << slot) - 1)).count_ones()) as usize);
        let first = prims.as_ptr().wrapping_add((n.prim_base + (meta & 31)) as usize);
        prefetch(if is_inner == 1 { child.cast::<i8>() } else { first.cast::<i8>() });
    }
    hits
}

/// The ray as every node's slab test takes it: origin, `safe_inverse` of the direction, and
/// per axis whether the low bound is met first (the direction is not negative).
pub struct Slabs<T> {
    o: [T; 3],
    inv: [T; 3],
    near_lo: [bool; 3],
}

impl<T: Real> Slabs<T> {
    #[inline(always)]
    fn new(o: V3<T>, inv: V3<T>) -> Self {
        let inv = [inv.x, inv.y, inv.z];
        Slabs { o: [o.x, o.y, o.z], inv, near_lo: inv.map(|i| i >= T::zero()) }
    }
}

/// Hints the cache to load the bytes from `p` on: a PREFETCHT0 at `p`, 72 and 143 bytes on,
/// which covers a wide node (80 bytes) or a leaf's at most 3 primitives (144 bytes) wherever
/// the cache lines fall (x86-64; elsewhere nothing).
#[inline(always)]
fn prefetch(p: *const i8) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch reads nothing architecturally and never faults, whatever the
        // address; the addresses are only formed with wrapping arithmetic.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(p);
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(72));
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(143));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
