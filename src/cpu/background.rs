//! Radiance of escaped rays; twin of `shaders/shared/background.wgsl`.

use super::{real::Real, vec3::V3};
use crate::scene::Background;

#[inline(always)]
pub fn background<T: Real>(bg: &Background, dir: V3<T>) -> V3<T> {
    match bg {
        Background::Sky => {
            let a = T::of(0.5) * (dir.y + T::one());
            V3::splat(T::one() - a) + V3::new(T::of(0.5), T::of(0.7), T::one()) * a
        }
        Background::Constant(c) => V3::of(c.to_array()),
    }
}
