//! A ray with a unit-length direction (every method normalises, so `t` is a distance).

use super::{real::Real, vec3::V3};

#[derive(Clone, Copy, Debug)]
pub struct Ray<T> {
    pub origin: V3<T>,
    pub dir: V3<T>,
}

impl<T: Real> Ray<T> {
    #[inline(always)]
    pub fn at(&self, t: T) -> V3<T> {
        self.origin + self.dir * t
    }
}

/// The book's shadow-acne guard: nearest intersections closer than this are ignored
/// (`--ray-offset tmin`, the default; `numerics.rs` has the others).
pub const T_MIN: f32 = crate::numerics::RayOffset::BOOK_T_MIN;
