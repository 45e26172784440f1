//! Warping uniform numbers to directions; twin of `shaders/shared/sampling.wgsl`. Closed-form
//! maps rather than the book's rejection loops, so every path uses a fixed number of draws.

use super::{real::Real, vec3::V3};

/// Uniform direction on the unit sphere.
#[inline(always)]
pub fn unit_vector<T: Real>(u1: f32, u2: f32) -> V3<T> {
    let z = T::one() - T::of(2.0) * T::of(u1);
    let r = (T::one() - z * z).max(T::zero()).sqrt();
    let phi = T::of(2.0) * T::PI() * T::of(u2);
    V3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform point in the unit disk, as (x, y).
#[inline(always)]
pub fn in_unit_disk<T: Real>(u1: f32, u2: f32) -> (T, T) {
    let r = T::of(u1).sqrt();
    let phi = T::of(2.0) * T::PI() * T::of(u2);
    (r * phi.cos(), r * phi.sin())
}
