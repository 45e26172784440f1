//! `enclosure`: a closed diffuse sphere lit by an emitting sphere at its centre, whose image is
//! known in closed form, for testing lights and next-event estimation (DESIGN.md §4).
//!
//! The camera sits inside a sphere of radius R = 10 with albedo ρ = 0.5, looking away from an
//! emitting sphere of radius r = 3 and radiance Le = 5 at the centre; every pixel sees the wall.
//! From any point of the wall the emitter fills a cone about the normal whose cosine-weighted
//! share of the hemisphere is s = (r/R)², and the rest of the hemisphere sees wall, which by
//! symmetry has the same radiance everywhere. With n rays left after the camera ray,
//!
//! ```text
//! L(n) = ρ s Le · Σ_{k<n} (ρ (1 − s))^k,      pixel value = L(max_depth − 1)
//! ```

use glam::Vec3;

use super::{Background, CameraSpec, Material, NamedMaterial, Scene, Sphere};

pub const WALL_RADIUS: f32 = 10.0;
pub const WALL_ALBEDO: f32 = 0.5;
pub const LIGHT_RADIUS: f32 = 3.0;
pub const LIGHT_RADIANCE: f32 = 5.0;

pub fn enclosure() -> Scene {
    Scene {
        name: "enclosure".into(),
        camera: CameraSpec {
            lookfrom: Vec3::new(0.0, 0.0, 5.0),
            lookat: Vec3::new(0.0, 0.0, 10.0),
            vup: Vec3::Y,
            vfov: 40.0,
            defocus_angle: 0.0,
            focus_dist: 1.0,
        },
        background: Background::Constant(Vec3::ZERO),
        materials: vec![
            NamedMaterial {
                name: "wall".into(),
                material: Material::Lambertian { albedo: Vec3::splat(WALL_ALBEDO).into() },
            },
            NamedMaterial {
                name: "light".into(),
                material: Material::Emissive { radiance: Vec3::splat(LIGHT_RADIANCE) },
            },
        ],
        spheres: vec![
            Sphere { center: Vec3::ZERO, radius: WALL_RADIUS, material: 0 },
            Sphere { center: Vec3::ZERO, radius: LIGHT_RADIUS, material: 1 },
        ],
        quads: Vec::new(),
        meshes: Vec::new(),
        images: Vec::new(),
    }
}

/// The exact radiance of every pixel at `max_depth` (rays per path, camera ray included).
pub fn exact_radiance(max_depth: u32) -> f64 {
    let (rho, le) = (WALL_ALBEDO as f64, LIGHT_RADIANCE as f64);
    let s = (LIGHT_RADIUS as f64 / WALL_RADIUS as f64).powi(2);
    let q = rho * (1.0 - s);
    let n = max_depth.saturating_sub(1) as i32;
    rho * s * le * (1.0 - q.powi(n)) / (1.0 - q)
}
