//! Whether a scene's arithmetic stays inside a method's floating-point range. A scene whose
//! squared distances or edge products overflow f32 (or whose quads are so small that theirs
//! underflow) does not fail loudly: a sphere of radius 1e38 around the camera has an infinite
//! squared radius, no ray hits it, and the image shows open sky with no NaN to warn anyone. So
//! such a scene is refused on the methods that compute in f32, with the limit named; `cpu-f64`
//! renders it (every f32 value squared fits in f64).

use crate::camera::CameraFrame;
use crate::layout::primitive_kind;
use crate::packed_scene::PackedScene;
use glam::DVec3;

/// Largest squared distance between two points of the scene (camera included) the intersection
/// tests form: |o − c|² with every coordinate below `extent` is at most 3·(2·extent)².
fn squared_distance_bound(extent: f64) -> f64 {
    12.0 * extent * extent
}

/// Refuses, for f32 arithmetic, a scene (after any stress transform) whose intermediate values
/// leave f32's range; the message names the quantity, its size and the limit.
pub fn check_f32(scene: &PackedScene, camera: &CameraFrame) -> Result<(), String> {
    let max = f32::MAX as f64;
    let mut extent = camera.center.abs().max_element().max(camera.pixel00.abs().max_element());
    let mut largest_edges = 0.0f64;
    let mut smallest_edges = f64::INFINITY;
    for p in &scene.primitives {
        let a = DVec3::from(p.a.map(f64::from));
        if p.kind == primitive_kind::SPHERE {
            extent = extent.max(a.abs().max_element() + p.radius as f64);
        } else {
            let (b, c) = (DVec3::from(p.b.map(f64::from)), DVec3::from(p.c.map(f64::from)));
            extent = extent.max((a.abs() + b.abs() + c.abs()).max_element());
            // |b × c|² is formed for the plane's normal: at most (|b|·|c|)².
            let edges = b.length() * c.length();
            largest_edges = largest_edges.max(edges);
            smallest_edges = smallest_edges.min(edges);
        }
    }
    let d2 = squared_distance_bound(extent);
    if !(0.0..max).contains(&d2) {
        return Err(format!(
            "the scene overflows f32 arithmetic: its coordinates (camera included) reach {extent:.3e}, \
             so squared distances in the intersection tests reach {d2:.3e}, past f32's largest \
             {max:.3e} (coordinates must stay below {:.3e}); render with --method cpu-f64, or \
             shrink the scene (--scale)",
            (max / 12.0).sqrt()
        ));
    }
    if !(0.0..max).contains(&(largest_edges * largest_edges)) {
        return Err(format!(
            "the scene overflows f32 arithmetic: a quad or triangle's edge lengths multiply to \
             {largest_edges:.3e}, so its squared normal |b × c|² reaches {:.3e}, past f32's \
             largest {max:.3e}; render with --method cpu-f64, or shrink the scene (--scale)",
            largest_edges * largest_edges
        ));
    }
    let min = f32::MIN_POSITIVE as f64;
    // Camera rays are normalised from offsets of about a pixel's spacing on the focus plane.
    let spacing = camera.pixel_delta_u.length().min(camera.pixel_delta_v.length());
    if !(min..=f64::MAX).contains(&(spacing * spacing)) {
        return Err(format!(
            "the scene underflows f32 arithmetic: the camera's pixels are {spacing:.3e} apart on              the focus plane, so squared ray directions fall below f32's smallest normal              {min:.3e}; render with --method cpu-f64, or enlarge the scene (--scale)"
        ));
    }
    if smallest_edges.is_finite() && !(min..=f64::MAX).contains(&(smallest_edges * smallest_edges)) {
        return Err(format!(
            "the scene underflows f32 arithmetic: a quad or triangle's edge lengths multiply to \
             {smallest_edges:.3e}, so its squared normal |b × c|² falls below f32's smallest \
             normal {min:.3e}; render with --method cpu-f64, or enlarge the scene (--scale)"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin;
    use crate::scene::stress::StressTransform;
    use crate::settings::Accel;

    fn check(name: &str, t: StressTransform) -> Result<(), String> {
        let scene = t.apply(&builtin::by_name(name).unwrap()).unwrap();
        let camera = CameraFrame::new(&scene.camera, 16, 16);
        check_f32(&PackedScene::new(&scene, Accel::Bvh), &camera)
    }

    #[test]
    fn the_stability_sweeps_fit_and_their_extremes_do_not() {
        for s in [1e-4, 1.0, 1e6] {
            check("cornell", StressTransform { scale: s, ..Default::default() }).unwrap();
            check("three-spheres", StressTransform { scale: s, ..Default::default() }).unwrap();
        }
        check("cornell", StressTransform { translate: [1e7; 3], ..Default::default() }).unwrap();
        // Cornell's 555-unit walls at 1e8: edge products of 3e21, squared 9e42.
        let e = check("cornell", StressTransform { scale: 1e8, ..Default::default() }).unwrap_err();
        assert!(e.contains("|b × c|²"), "{e}");
        let e = check("three-spheres", StressTransform { scale: 1e17, ..Default::default() }).unwrap_err();
        assert!(e.contains("squared distances"), "{e}");
        // 555 × 1e-21 per edge: products of 3e-37, squared 1e-73.
        let e = check("cornell", StressTransform { scale: 1e-21, ..Default::default() }).unwrap_err();
        assert!(e.contains("underflows"), "{e}");
    }
}
