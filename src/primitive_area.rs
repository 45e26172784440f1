//! A primitive's surface area, generic over f32/f64: the lights' power when the scene is packed
//! (f64, `packed_scene.rs`) and the CPU's light densities (`cpu/light.rs`, re-exported by
//! `cpu/primitive.rs`); twin of `primitive_area` in `shaders/shared/primitive.wgsl`. Below `cpu`,
//! so packing a scene does not depend on the CPU renderer.

use crate::layout::{primitive_kind, PrimitiveRecord};
use crate::real::Real;
use crate::vec3::V3;

/// Surface area.
#[inline(always)]
pub fn area<T: Real>(p: &PrimitiveRecord) -> T {
    match p.kind {
        primitive_kind::SPHERE => T::of(4.0) * T::PI() * T::of(p.radius) * T::of(p.radius),
        primitive_kind::QUAD => V3::<T>::of(p.b).cross(V3::of(p.c)).length(),
        _ => T::of(0.5) * V3::<T>::of(p.b).cross(V3::of(p.c)).length(),
    }
}
