//! `two-lights`: a room lit by one small bright sphere light and one large dim quad light, the
//! case where how next-event estimation samples lights shows (`experiments/light_sampling.json`).
//!
//! The sphere (radius 0.15, radiance 100) emits about 35× the quad's power (4 × 4 under the open
//! top, radiance 0.05) and lights most of the floor and walls, so choosing each light half the
//! time (`--light-select uniform`) spends half the shadow rays on the light that matters least;
//! and sampling the sphere by area (`--light-sampling area`) puts about half of its points on the
//! side the sphere itself hides. Floor, back wall (albedo 0.5) and two coloured side walls are
//! diffuse; the room is open towards the camera and has no ceiling, the background is black.
//! (How much power-proportional choice gains depends on how unequal the lights are: with the
//! panel at radiance 0.25, 7× less unequal, it gained about 1.5× at equal samples.)

use glam::Vec3;

use super::{Background, CameraSpec, Material, NamedMaterial, Quad, Scene, Sphere};

pub const SPHERE_CENTER: Vec3 = Vec3::new(1.0, 0.7, -0.6);
pub const SPHERE_RADIUS: f32 = 0.15;
pub const SPHERE_RADIANCE: f32 = 100.0;
pub const PANEL_SIZE: f32 = 4.0;
pub const PANEL_RADIANCE: f32 = 0.05;

pub fn two_lights() -> Scene {
    let lambertian = |name: &str, c: [f32; 3]| NamedMaterial {
        name: name.into(),
        material: Material::Lambertian { albedo: Vec3::from(c).into() },
    };
    let emitter = |name: &str, le: f32| NamedMaterial {
        name: name.into(),
        material: Material::Emissive { radiance: Vec3::splat(le) },
    };
    let materials = vec![
        lambertian("white", [0.5, 0.5, 0.5]),
        lambertian("red", [0.65, 0.05, 0.05]),
        lambertian("green", [0.12, 0.45, 0.15]),
        emitter("bulb", SPHERE_RADIANCE),
        emitter("panel", PANEL_RADIANCE),
    ];
    let (white, red, green, bulb, panel) = (0, 1, 2, 3, 4);
    let q = |corner: [f32; 3], u: [f32; 3], v: [f32; 3], material| Quad {
        corner: corner.into(),
        u: u.into(),
        v: v.into(),
        material,
    };
    let half = PANEL_SIZE / 2.0;
    Scene {
        name: "two-lights".into(),
        camera: CameraSpec {
            lookfrom: Vec3::new(0.0, 1.6, 6.0),
            lookat: Vec3::new(0.0, 1.1, 0.0),
            vup: Vec3::Y,
            vfov: 45.0,
            defocus_angle: 0.0,
            focus_dist: 1.0,
        },
        background: Background::Constant(Vec3::ZERO),
        materials,
        spheres: vec![Sphere { center: SPHERE_CENTER, radius: SPHERE_RADIUS, material: bulb }],
        quads: vec![
            q([-3.0, 0.0, -3.0], [6.0, 0.0, 0.0], [0.0, 0.0, 6.0], white), // floor
            q([-3.0, 0.0, -3.0], [0.0, 3.2, 0.0], [6.0, 0.0, 0.0], white), // back wall
            q([-3.0, 0.0, -3.0], [0.0, 0.0, 6.0], [0.0, 3.2, 0.0], red),   // left wall
            q([3.0, 0.0, -3.0], [0.0, 3.2, 0.0], [0.0, 0.0, 6.0], green),  // right wall
            q([-half, 3.0, -half], [PANEL_SIZE, 0.0, 0.0], [0.0, 0.0, PANEL_SIZE], panel),
        ],
        meshes: Vec::new(),
        images: Vec::new(),
    }
}
