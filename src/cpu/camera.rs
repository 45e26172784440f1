//! Camera rays; twin of `shaders/shared/camera.wgsl`. Directions are formed from offsets relative
//! to the camera centre, never from world-space points on the focus plane: far from the origin
//! those are rounded to the coordinates' ulp, which on a plane `focus_dist` away becomes
//! direction error (the README's "Where methods fail — numerically").

use super::{ray::Ray, real::Real, sampling::in_unit_disk, vec3::V3};
use crate::camera::CameraFrame;

/// The camera frame converted once to the integrator's scalar.
#[derive(Clone, Copy, Debug)]
pub struct Camera<T> {
    center: V3<T>,
    /// Centre of pixel (0, 0) relative to `center`.
    pixel00_offset: V3<T>,
    delta_u: V3<T>,
    delta_v: V3<T>,
    disk_u: V3<T>,
    disk_v: V3<T>,
    has_defocus: bool,
}

impl<T: Real> Camera<T> {
    /// f32 methods see the frame rounded to f32 exactly as the GPU's uniform holds it.
    pub fn new(f: &CameraFrame) -> Self {
        let c = |v: glam::DVec3| {
            if std::mem::size_of::<T>() == 4 {
                V3::of(v.as_vec3().to_array())
            } else {
                V3::of64(v)
            }
        };
        Self {
            center: c(f.center),
            pixel00_offset: c(f.pixel00 - f.center),
            delta_u: c(f.pixel_delta_u),
            delta_v: c(f.pixel_delta_v),
            disk_u: c(f.defocus_disk_u),
            disk_v: c(f.defocus_disk_v),
            has_defocus: f.has_defocus,
        }
    }

    /// The ray through pixel (x, y) jittered by `u[0..2]`, from the lens point `u[2..4]`.
    #[inline(always)]
    pub fn ray(&self, x: u32, y: u32, u: [f32; 4]) -> Ray<T> {
        let half = T::of(0.5);
        let px = T::of(x as f32) + (T::of(u[0]) - half);
        let py = T::of(y as f32) + (T::of(u[1]) - half);
        let to_target = self.pixel00_offset + self.delta_u * px + self.delta_v * py;
        let lens = if self.has_defocus {
            let (dx, dy) = in_unit_disk::<T>(u[2], u[3]);
            self.disk_u * dx + self.disk_v * dy
        } else {
            V3::splat(T::zero())
        };
        Ray { origin: self.center + lens, dir: (to_target - lens).normalize() }
    }
}
