//! The camera frame of Ray Tracing in One Weekend (4th edition), computed once on the host in
//! f64 and handed to every method, so all of them start rays from the same numbers.

use crate::scene::CameraSpec;
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    pub center: DVec3,
    /// Centre of pixel (0, 0), the top-left one.
    pub pixel00: DVec3,
    pub pixel_delta_u: DVec3,
    pub pixel_delta_v: DVec3,
    pub defocus_disk_u: DVec3,
    pub defocus_disk_v: DVec3,
    /// False for a pinhole (defocus angle 0): rays start at `center`.
    pub has_defocus: bool,
}

impl CameraFrame {
    pub fn new(spec: &CameraSpec, width: u32, height: u32) -> Self {
        let lookfrom = spec.lookfrom.as_dvec3();
        let lookat = spec.lookat.as_dvec3();
        let vup = spec.vup.as_dvec3();
        let focus_dist = spec.focus_dist as f64;
        let h = (f64::from(spec.vfov).to_radians() / 2.0).tan();
        let viewport_height = 2.0 * h * focus_dist;
        let viewport_width = viewport_height * (width as f64 / height as f64);
        let w = (lookfrom - lookat).normalize();
        let u = vup.cross(w).normalize();
        let v = w.cross(u);
        let viewport_u = viewport_width * u;
        let viewport_v = viewport_height * -v;
        let pixel_delta_u = viewport_u / width as f64;
        let pixel_delta_v = viewport_v / height as f64;
        let upper_left = lookfrom - focus_dist * w - viewport_u / 2.0 - viewport_v / 2.0;
        let defocus_radius = focus_dist * (f64::from(spec.defocus_angle) / 2.0).to_radians().tan();
        Self {
            center: lookfrom,
            pixel00: upper_left + 0.5 * (pixel_delta_u + pixel_delta_v),
            pixel_delta_u,
            pixel_delta_v,
            defocus_disk_u: u * defocus_radius,
            defocus_disk_v: v * defocus_radius,
            has_defocus: spec.defocus_angle > 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_at_lookat() {
        let spec = crate::scene::builtin::rtiow_camera();
        let f = CameraFrame::new(&spec, 201, 101);
        let centre = f.pixel00 + 100.0 * f.pixel_delta_u + 50.0 * f.pixel_delta_v;
        let dir = (centre - f.center).normalize();
        let want = (DVec3::ZERO - f.center).normalize();
        assert!(dir.distance(want) < 1e-12);
        // The focus plane sits focus_dist away along the view axis.
        assert!(((centre - f.center).length() - 10.0).abs() < 1e-9);
        // v points down the image: row 1 is below row 0.
        assert!(f.pixel_delta_v.y < 0.0);
    }
}
