//! The CPU reference renderer: the accuracy ground truth and the seeds' CPU baseline. Rows are
//! spread over threads with rayon; every sample's random numbers come from [`crate::rng`], so the
//! result does not depend on the number of threads.

pub mod background;
pub mod bvh;
pub mod bvh_aila_laine;
pub mod bvh_wide;
pub mod camera;
pub mod image_texture;
pub mod integrator;
pub mod light;
pub mod material;
pub mod observe;
pub mod offset;
pub mod planar;
pub mod primitive;
pub mod ray;
pub mod sampling;
pub mod sphere;
pub mod texture;
pub mod traversal_counts;

// The arithmetic the reference is generic over lives below it, where packed_scene uses it too.
pub use crate::{real, vec3};

use crate::camera::CameraFrame;
use crate::film::{Film, PixelStats};
use crate::numerics::Failures;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use rayon::prelude::*;
use real::Real;

/// Renders with the integrator computing in `T`; `on_row` is called once per finished row.
/// Returns the film and what failed numerically on the way.
pub fn render<T: Real>(
    scene: &PackedScene,
    frame: &CameraFrame,
    settings: &RenderSettings,
    on_row: &(dyn Fn() + Sync),
) -> (Film, Failures) {
    let camera = camera::Camera::<T>::new(frame);
    let w = settings.width;
    let mut film = Film::new(w, settings.height, settings.spp);
    let failures = std::sync::Mutex::new(Failures::default());
    film.pixels.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
        // A requested stop (`cancel.rs`: the Python package's Ctrl-C) ends the rows not yet
        // started at once, not after each has been traced.
        crate::cancel::checkpoint();
        let mut row_failures = Failures::default();
        for (x, px) in row.iter_mut().enumerate() {
            let mut stats = PixelStats::default();
            for s in 0..settings.spp {
                let path = integrator::trace_path(scene, &camera, settings, x as u32, y as u32, s, &mut ());
                stats.add(path.radiance.to_f64());
                stats.rays += path.rays as u64;
                row_failures.add(&path.failures);
            }
            *px = stats;
        }
        failures.lock().expect("no thread panics holding it").add(&row_failures);
        on_row();
    });
    (film, failures.into_inner().expect("no thread panicked holding it"))
}
