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

/// Two unit vectors completing the unit vector `n` to an orthonormal frame, without branches on
/// the angle (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
#[inline(always)]
pub fn orthonormal_basis<T: Real>(n: V3<T>) -> (V3<T>, V3<T>) {
    let sign = if n.z >= T::zero() { T::one() } else { -T::one() };
    let a = -T::one() / (sign + n.z);
    let b = n.x * n.y * a;
    (V3::new(T::one() + sign * n.x * n.x * a, sign * b, -sign * n.x), V3::new(b, sign + n.y * n.y * a, -n.y))
}
