//! Built-in scenes, selected by name (`--scene rtiow-final`).
//!
//! # `rtiow-final`: the layout
//!
//! The book's final scene (Ray Tracing in One Weekend, 4th edition, "A Final Render") draws its
//! layout from an unseeded `rand()`, so every reader's image differs. Ours comes from
//! [`rng::Stream::new(RTIOW_FINAL_SEED)`](crate::rng::Stream), drawn in exactly this order:
//!
//! ```text
//! for a in -11..11:                      (outer)
//!   for b in -11..11:                    (inner)
//!     choose_mat = u()
//!     center     = (a + 0.9 u(), 0.2, b + 0.9 u())     x drawn before z
//!     if |center - (4, 0.2, 0)| > 0.9:
//!       choose_mat < 0.8  -> lambertian, albedo = (u(), u(), u()) * (u(), u(), u())
//!                            (componentwise; the first vector is drawn first)
//!       choose_mat < 0.95 -> metal, albedo = (0.5 + 0.5 u()) per component (r, g, b),
//!                            then fuzz = 0.5 u()
//!       otherwise         -> dielectric, ior 1.5 (no draws)
//!       radius 0.2
//! ```
//!
//! `u()` is [`Stream::next_f32`](crate::rng::Stream::next_f32) (or
//! [`Stream::range`](crate::rng::Stream::range) for the metal values), all arithmetic in f32. A
//! skipped cell still consumes its three draws. Each small sphere has its own material, named
//! `small-a<a>-b<b>` after its cell (`small-a-11-b3`); the fixed ones are `ground`, `glass`,
//! `brown` and `mirror`. Materials are listed in creation order: ground, the small ones, then
//! glass, brown, mirror; spheres likewise.

use glam::Vec3;

use super::{Background, CameraSpec, Material, NamedMaterial, Scene, Sphere};
use crate::rng::Stream;

/// The stream id of the `rtiow-final` layout. Changing it changes the scene.
pub const RTIOW_FINAL_SEED: u32 = 1;

/// A built-in scene: its name, a one-line description, and how to build it.
pub struct Builtin {
    pub name: &'static str,
    pub description: &'static str,
    pub build: fn() -> Scene,
}

/// Every built-in scene, in the order `wavetrace scene list` shows them.
pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "rtiow-final",
        description: "Ray Tracing in One Weekend's final scene: ground, 484-cell grid of small \
                      spheres (80% diffuse, 15% metal, 5% glass), three big spheres; seeded layout",
        build: rtiow_final,
    },
    Builtin {
        name: "three-spheres",
        description: "The final scene's ground and three big spheres (glass, diffuse, mirror) only",
        build: three_spheres,
    },
    Builtin {
        name: "furnace",
        description: "Furnace test: a diffuse sphere (albedo 0.5) under uniform white light; exact \
                      image is 0.5 on the sphere, 1 elsewhere",
        build: furnace,
    },
];

const NAMES: &[&str] = &["rtiow-final", "three-spheres", "furnace"];

/// The names of the built-in scenes, in [`BUILTINS`] order.
pub fn names() -> &'static [&'static str] {
    NAMES
}

/// `(name, one-line description)` for each built-in scene.
pub fn list() -> Vec<(&'static str, &'static str)> {
    BUILTINS.iter().map(|b| (b.name, b.description)).collect()
}

/// The built-in scene called `name`, if there is one.
pub fn by_name(name: &str) -> Option<Scene> {
    BUILTINS.iter().find(|b| b.name == name).map(|b| (b.build)())
}

/// Collects materials and spheres; each sphere refers to a material by its index.
struct Builder {
    materials: Vec<NamedMaterial>,
    spheres: Vec<Sphere>,
}

impl Builder {
    fn new() -> Self {
        Self { materials: Vec::new(), spheres: Vec::new() }
    }

    fn add(&mut self, material_name: String, material: Material, center: Vec3, radius: f32) {
        self.spheres.push(Sphere { center, radius, material: self.materials.len() as u32 });
        self.materials.push(NamedMaterial { name: material_name, material });
    }

    fn finish(self, name: &str, camera: CameraSpec, background: Background) -> Scene {
        Scene { name: name.to_owned(), camera, background, materials: self.materials, spheres: self.spheres }
    }
}

/// The book's final camera.
fn rtiow_camera() -> CameraSpec {
    CameraSpec {
        lookfrom: Vec3::new(13.0, 2.0, 3.0),
        lookat: Vec3::ZERO,
        vup: Vec3::Y,
        vfov: 20.0,
        defocus_angle: 0.6,
        focus_dist: 10.0,
    }
}

fn add_ground(b: &mut Builder) {
    let ground = Material::Lambertian { albedo: Vec3::splat(0.5) };
    b.add("ground".into(), ground, Vec3::new(0.0, -1000.0, 0.0), 1000.0);
}

fn add_big_three(b: &mut Builder) {
    b.add("glass".into(), Material::Dielectric { ior: 1.5 }, Vec3::new(0.0, 1.0, 0.0), 1.0);
    let brown = Material::Lambertian { albedo: Vec3::new(0.4, 0.2, 0.1) };
    b.add("brown".into(), brown, Vec3::new(-4.0, 1.0, 0.0), 1.0);
    let mirror = Material::Metal { albedo: Vec3::new(0.7, 0.6, 0.5), fuzz: 0.0 };
    b.add("mirror".into(), mirror, Vec3::new(4.0, 1.0, 0.0), 1.0);
}

fn rtiow_final() -> Scene {
    let mut rng = Stream::new(RTIOW_FINAL_SEED);
    let mut b = Builder::new();
    add_ground(&mut b);
    for a in -11..11 {
        for bb in -11..11 {
            let choose_mat = rng.next_f32();
            let x = a as f32 + 0.9 * rng.next_f32();
            let z = bb as f32 + 0.9 * rng.next_f32();
            let center = Vec3::new(x, 0.2, z);
            if (center - Vec3::new(4.0, 0.2, 0.0)).length() <= 0.9 {
                continue;
            }
            let material = if choose_mat < 0.8 {
                let v1 = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let v2 = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                Material::Lambertian { albedo: v1 * v2 }
            } else if choose_mat < 0.95 {
                let albedo = Vec3::new(rng.range(0.5, 1.0), rng.range(0.5, 1.0), rng.range(0.5, 1.0));
                Material::Metal { albedo, fuzz: rng.range(0.0, 0.5) }
            } else {
                Material::Dielectric { ior: 1.5 }
            };
            b.add(format!("small-a{a}-b{bb}"), material, center, 0.2);
        }
    }
    add_big_three(&mut b);
    b.finish("rtiow-final", rtiow_camera(), Background::Sky)
}

fn three_spheres() -> Scene {
    let mut b = Builder::new();
    add_ground(&mut b);
    add_big_three(&mut b);
    b.finish("three-spheres", rtiow_camera(), Background::Sky)
}

/// A unit sphere seen from distance 4 subtends asin(1/4) ~ 14.5 degrees either side of the
/// axis: about 72% of the 40-degree frame's height, background all round it.
fn furnace() -> Scene {
    let mut b = Builder::new();
    let grey = Material::Lambertian { albedo: Vec3::splat(0.5) };
    b.add("grey".into(), grey, Vec3::ZERO, 1.0);
    let camera = CameraSpec {
        lookfrom: Vec3::new(0.0, 0.0, 4.0),
        lookat: Vec3::ZERO,
        vup: Vec3::Y,
        vfov: 40.0,
        defocus_angle: 0.0,
        focus_dist: 4.0,
    };
    b.finish("furnace", camera, Background::Constant(Vec3::ONE))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_the_table() {
        let table: Vec<&str> = BUILTINS.iter().map(|b| b.name).collect();
        assert_eq!(names(), table.as_slice());
        for (name, _) in list() {
            assert_eq!(by_name(name).expect("listed scene builds").name, name);
        }
        assert!(by_name("no-such-scene").is_none());
    }

    #[test]
    fn final_scene_mix_is_roughly_the_books() {
        let scene = by_name("rtiow-final").unwrap();
        let small = &scene.materials[1..scene.materials.len() - 3];
        let count = |kind| small.iter().filter(|m| m.material.kind_name() == kind).count() as f32;
        let n = small.len() as f32;
        // 80% / 15% / 5% of ~484 cells: a few standard deviations of slack.
        assert!((count("lambertian") / n - 0.80).abs() < 0.06);
        assert!((count("metal") / n - 0.15).abs() < 0.05);
        assert!((count("dielectric") / n - 0.05).abs() < 0.03);
        for m in small {
            match m.material {
                Material::Metal { albedo, fuzz } => {
                    assert!(albedo.min_element() >= 0.5 && albedo.max_element() < 1.0);
                    assert!((0.0..0.5).contains(&fuzz));
                }
                Material::Lambertian { albedo } => {
                    assert!(albedo.min_element() >= 0.0 && albedo.max_element() < 1.0)
                }
                Material::Dielectric { ior } => assert_eq!(ior, 1.5),
                Material::Emissive { .. } => panic!("no lights in the final scene"),
            }
        }
    }
}
