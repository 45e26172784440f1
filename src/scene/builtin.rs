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
//!
//! # `spheres-N`: the scale family
//!
//! `spheres-N` for any N in 1..=[`SPHERES_MAX`] (written without leading zeros) is the book's
//! ground with N small spheres in a square grid of side `s = ceil(sqrt(N))`, filled row by row
//! (`ceil(N / s)` rows), under the sky. Cells are 1 unit wide up to the book's 22 per side; past
//! that the grid keeps the book's 22-unit footprint and cells shrink to `22 / s`, so the camera
//! frames the same picture at every N and only the geometry's density (and the BVH's depth)
//! grows. In cell units each sphere has radius 0.2 and its centre is jittered by at most 0.25
//! per axis, so neighbours stay at least 0.5 apart and never overlap; each sits on the curved
//! ground (centre at distance 1000 + r from the ground's centre). Drawn from
//! [`Stream::new(SPHERES_SEED)`](crate::rng::Stream), per sphere in grid order:
//!
//! ```text
//! choose_mat = u(); jitter x = u() - 0.5, then z, times 0.5 cell
//! then the material as in rtiow-final (80% lambertian, 15% metal, 5% dielectric)
//! ```
//!
//! Each sphere has its own material, `small-<k>` for the k-th sphere; the ground is `ground`
//! (materials and spheres: ground first, then the grid in order).

use glam::Vec3;

use super::{Background, CameraSpec, Material, NamedMaterial, Scene, Sphere};
use crate::rng::Stream;

/// The stream id of the `rtiow-final` layout. Changing it changes the scene.
pub const RTIOW_FINAL_SEED: u32 = 1;

/// The stream id of the `spheres-N` layouts. Changing it changes those scenes.
pub const SPHERES_SEED: u32 = 2;

/// The `triangles-N` entry of [`BUILTINS`] (like [`SPHERES_EXAMPLE`]).
const TRIANGLES_EXAMPLE: u32 = 10_000;

/// The largest N of `spheres-N`.
pub const SPHERES_MAX: u32 = 1_000_000;

/// The `spheres-N` entry of [`BUILTINS`]: one member of the family stands for all of it, so that
/// every listed name builds (`scene list` counts its spheres, exports round-trip).
const SPHERES_EXAMPLE: u32 = 1000;

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
        name: "rtiow-heavy",
        description: "rtiow-final made costly to shade (rtiow-heavy-O: O in 1..=16 octaves of noise, \
                      here 8): checker ground, noise or marble on every diffuse sphere",
        build: || super::heavy::rtiow_heavy(rtiow_final(), super::heavy::DEFAULT_OCTAVES),
    },
    Builtin {
        name: "rtiow-kinds-8",
        description: "rtiow-kinds-K, any K in 1..=8 (here 8): rtiow-heavy's layout with each diffuse \
                      sphere one of K distinct costly patterns (noise, marble, wood, ridged, warp, \
                      cellular, crackle, value), 8 octaves each",
        build: || super::kinds::rtiow_kinds(rtiow_final(), super::kinds::MAX_KINDS),
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
    Builtin {
        name: "cornell",
        description: "The Next Week's Cornell box: five walls and two rotated boxes as quads, a \
                      130x105 light of radiance 15, black background",
        build: super::cornell::cornell,
    },
    Builtin {
        name: "enclosure",
        description: "Camera inside a closed diffuse sphere lit by an emitting sphere at its centre; \
                      exact image known in closed form (tests lights and --nee)",
        build: super::enclosure::enclosure,
    },
    Builtin {
        name: "two-lights",
        description: "A room lit by a small bright sphere light and a large dim quad light: where \
                      --light-select and --light-sampling show",
        build: super::two_lights::two_lights,
    },
    Builtin {
        name: "triangles-10000",
        description: "triangles-N, any N in 1..=10000000 (here 10000): a generated terrain of N \
                      triangles under the final scene's camera and its three big spheres (scene size)",
        build: || super::terrain::scene(three_spheres(), TRIANGLES_EXAMPLE),
    },
    Builtin {
        name: "spheres-1000",
        description: "spheres-N, any N in 1..=1000000 (here 1000): N small spheres (80% diffuse, \
                      15% metal, 5% glass) in a seeded square grid on the ground, whole grid in view",
        build: || spheres(SPHERES_EXAMPLE),
    },
];

const NAMES: &[&str] = &[
    "rtiow-final",
    "rtiow-heavy",
    "rtiow-kinds-8",
    "three-spheres",
    "furnace",
    "cornell",
    "enclosure",
    "two-lights",
    "triangles-10000",
    "spheres-1000",
];

/// The names of the built-in scenes, in [`BUILTINS`] order.
pub fn names() -> &'static [&'static str] {
    NAMES
}

/// `(name, one-line description)` for each built-in scene.
pub fn list() -> Vec<(&'static str, &'static str)> {
    BUILTINS.iter().map(|b| (b.name, b.description)).collect()
}

/// The built-in scene called `name`, if there is one: a [`BUILTINS`] entry, `spheres-N`,
/// `rtiow-heavy-O`, `rtiow-kinds-K` or `triangles-N`.
pub fn by_name(name: &str) -> Option<Scene> {
    match BUILTINS.iter().find(|b| b.name == name) {
        Some(b) => Some((b.build)()),
        None => spheres_count(name)
            .map(spheres)
            .or_else(|| super::heavy::parse_name(name).map(|o| super::heavy::rtiow_heavy(rtiow_final(), o)))
            .or_else(|| super::kinds::parse_name(name).map(|k| super::kinds::rtiow_kinds(rtiow_final(), k)))
            .or_else(|| super::terrain::parse_name(name).map(|n| super::terrain::scene(three_spheres(), n))),
    }
}

/// N of a well-formed `spheres-N` name: decimal digits without a leading zero or sign, N in
/// 1..=[`SPHERES_MAX`]; otherwise `None`, so that each scene has exactly one name.
pub fn spheres_count(name: &str) -> Option<u32> {
    super::family_number(name, "spheres-", 1..=SPHERES_MAX)
}

/// Why `arg` names no scene, when it is not a built-in and `file` (where `arg` leads as a path)
/// does not exist: the family rule it breaks, or the built-in names with the closest one.
/// Shared by `--scene` and experiment configs, so both say the same.
/// The file is named by the path it was resolved to (absolute), and a name that is clearly a
/// path (a folder in it, or a scene file's extension) is told so without the built-in names.
pub fn unknown_scene(arg: &str, file: &std::path::Path) -> String {
    let resolved = std::path::absolute(file).unwrap_or_else(|_| file.to_path_buf());
    if looks_like_a_path(arg) {
        return format!("no such scene file: {} does not exist", resolved.display());
    }
    family_hint(arg).unwrap_or_else(|| {
        format!(
            "{arg:?} is neither a built-in scene{} nor a file ({} does not exist); built-in scenes: {} \
             (`wavetrace scene list` describes them)",
            crate::strict_json::did_you_mean(arg, NAMES),
            resolved.display(),
            crate::strict_json::quoted_list(NAMES)
        )
    })
}

/// A folder in it or a scene file's extension: no built-in name looks like this.
fn looks_like_a_path(arg: &str) -> bool {
    let lower = arg.to_ascii_lowercase();
    arg.contains(['/', '\\']) || [".json", ".gltf", ".glb", ".obj"].iter().any(|e| lower.ends_with(e))
}

/// Why `name`, which looks like a member of a built-in family but is not one, names no scene; for
/// the "no such scene" error (`None` when `name` does not look like one).
pub fn family_hint(name: &str) -> Option<String> {
    if name.starts_with("triangles-") {
        return super::terrain::family_hint(name);
    }
    if name.starts_with("rtiow-kinds-") {
        return super::kinds::family_hint(name);
    }
    if let Some(digits) = name.strip_prefix("rtiow-heavy-") {
        return super::heavy::parse_name(name).is_none().then(|| {
            format!(
                "{name:?} is not a built-in scene: rtiow-heavy-O takes O in 1..={}, written without \
                 leading zeros (got {digits:?})",
                super::texture::MAX_OCTAVES
            )
        });
    }
    let digits = name.strip_prefix("spheres-")?;
    if spheres_count(name).is_some() {
        return None;
    }
    Some(format!(
        "{name:?} is not a built-in scene: spheres-N takes N in 1..={SPHERES_MAX}, written without \
         leading zeros (got {digits:?})"
    ))
}

/// The book's random small-sphere material for `choose_mat` in [0, 1): 80% diffuse (albedo a
/// product of two random colours), 15% metal, 5% glass; draws from `rng` in the book's order.
fn book_material(choose_mat: f32, rng: &mut Stream) -> Material {
    if choose_mat < 0.8 {
        let v1 = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let v2 = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        Material::Lambertian { albedo: (v1 * v2).into() }
    } else if choose_mat < 0.95 {
        let albedo = Vec3::new(rng.range(0.5, 1.0), rng.range(0.5, 1.0), rng.range(0.5, 1.0));
        Material::Metal { albedo: albedo.into(), fuzz: rng.range(0.0, 0.5) }
    } else {
        Material::Dielectric { ior: 1.5 }
    }
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
        Scene {
            name: name.to_owned(),
            camera,
            background,
            materials: self.materials,
            spheres: self.spheres,
            quads: Vec::new(),
            meshes: Vec::new(),
            images: Vec::new(),
        }
    }
}

/// The book's final camera.
pub(crate) fn rtiow_camera() -> CameraSpec {
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
    let ground = Material::Lambertian { albedo: Vec3::splat(0.5).into() };
    b.add("ground".into(), ground, Vec3::new(0.0, -1000.0, 0.0), 1000.0);
}

fn add_big_three(b: &mut Builder) {
    b.add("glass".into(), Material::Dielectric { ior: 1.5 }, Vec3::new(0.0, 1.0, 0.0), 1.0);
    let brown = Material::Lambertian { albedo: Vec3::new(0.4, 0.2, 0.1).into() };
    b.add("brown".into(), brown, Vec3::new(-4.0, 1.0, 0.0), 1.0);
    let mirror = Material::Metal { albedo: Vec3::new(0.7, 0.6, 0.5).into(), fuzz: 0.0 };
    b.add("mirror".into(), mirror, Vec3::new(4.0, 1.0, 0.0), 1.0);
}

pub(super) fn rtiow_final() -> Scene {
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
            let material = book_material(choose_mat, &mut rng);
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
    let grey = Material::Lambertian { albedo: Vec3::splat(0.5).into() };
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

/// `spheres-N` (see the module doc): N small spheres in a seeded grid on the ground.
fn spheres(n: u32) -> Scene {
    assert!((1..=SPHERES_MAX).contains(&n), "spheres-N takes N in 1..={SPHERES_MAX}, got {n}");
    let side = (n as f64).sqrt().ceil() as u32;
    let rows = n.div_ceil(side);
    // The book's grid is 22 cells of 1 unit; bigger grids keep its footprint.
    let cell = if side <= 22 { 1.0 } else { 22.0 / side as f32 };
    let radius = 0.2 * cell;
    let ground = Vec3::new(0.0, -1000.0, 0.0);
    let mut rng = Stream::new(SPHERES_SEED);
    let mut b = Builder::new();
    b.materials.reserve(n as usize + 1);
    b.spheres.reserve(n as usize + 1);
    add_ground(&mut b);
    for k in 0..n {
        let (i, j) = (k % side, k / side);
        let choose_mat = rng.next_f32();
        let x = (i as f32 - 0.5 * (side - 1) as f32 + 0.5 * (rng.next_f32() - 0.5)) * cell;
        let z = (j as f32 - 0.5 * (rows - 1) as f32 + 0.5 * (rng.next_f32() - 0.5)) * cell;
        // On the curved ground, not the plane y = 0: at the grid's edge the ground is ~0.06
        // below the plane, more than a small sphere's radius at large N.
        let center = ground + (1000.0 + radius) * (Vec3::new(x, 0.0, z) - ground).normalize();
        let material = book_material(choose_mat, &mut rng);
        b.add(format!("small-{k}"), material, center, radius);
    }
    b.finish(&format!("spheres-{n}"), spheres_camera(side as f32 * cell, rows as f32 * cell), Background::Sky)
}

/// Looks down on a `width` × `depth` grid centred at the origin from 25 degrees above the
/// ground and 25 degrees off its axis (a corner nearest, as in the book's view), at a distance
/// proportional to the grid, so the whole grid is in a 16:9 frame with a strip of sky above the
/// horizon at every N. Pinhole: the spheres are small enough that blur would hide them.
fn spheres_camera(width: f32, depth: f32) -> CameraSpec {
    let (elevation, azimuth) = (25f32.to_radians(), 25f32.to_radians());
    let extent = width.max(depth);
    let distance = 1.35 * extent;
    let dir = Vec3::new(azimuth.sin() * elevation.cos(), elevation.sin(), azimuth.cos() * elevation.cos());
    // Aimed a little above the grid's centre, which lowers the grid in the frame to show sky.
    let lookat = Vec3::new(0.0, 0.06 * extent, 0.0);
    CameraSpec {
        lookfrom: lookat + distance * dir,
        lookat,
        vup: Vec3::Y,
        vfov: 50.0,
        defocus_angle: 0.0,
        focus_dist: distance,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Texture;

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
    fn spheres_names_parse_strictly() {
        for (name, n) in [("spheres-1", 1), ("spheres-250", 250), ("spheres-1000000", SPHERES_MAX)] {
            assert_eq!(spheres_count(name), Some(n), "{name}");
            assert!(family_hint(name).is_none(), "{name}");
        }
        for bad in [
            "spheres-0",
            "spheres-01",
            "spheres-1000001",
            "spheres-2000000",
            "spheres-99999999999",
            "spheres-",
            "spheres-x",
            "spheres--5",
            "spheres-+5",
            "spheres- 5",
            "spheres-1e3",
            "spheres-N",
            "Spheres-5",
        ] {
            assert_eq!(spheres_count(bad), None, "{bad}");
            assert!(by_name(bad).is_none(), "{bad}");
        }
        let hint = family_hint("spheres-0").unwrap();
        assert!(hint.contains("1..=1000000") && hint.contains("\"0\""), "{hint}");
        assert!(family_hint("rtiow-finale").is_none());
    }

    #[test]
    fn spheres_n_builds_n_small_spheres_on_the_ground() {
        for n in [1, 2, 5, 22 * 22, 1000, 1001] {
            let scene = by_name(&format!("spheres-{n}")).unwrap();
            assert_eq!(scene.name, format!("spheres-{n}"));
            assert_eq!(scene.spheres.len(), n as usize + 1);
            assert_eq!(scene.materials.len(), n as usize + 1);
            scene.validate().unwrap();
            let ground = scene.spheres[0];
            for s in &scene.spheres[1..] {
                // Touching the ground up to f32 rounding at 1000 (ulp 6e-5): not sunk, not floating.
                let gap = s.center.distance(ground.center) - ground.radius - s.radius;
                assert!(gap.abs() < 5e-4, "spheres-{n}: gap {gap}");
                assert!(s.radius <= 0.2);
            }
        }
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
                Material::Metal { albedo: Texture::Solid(albedo), fuzz } => {
                    assert!(albedo.min_element() >= 0.5 && albedo.max_element() < 1.0);
                    assert!((0.0..0.5).contains(&fuzz));
                }
                Material::Lambertian { albedo: Texture::Solid(albedo) } => {
                    assert!(albedo.min_element() >= 0.0 && albedo.max_element() < 1.0)
                }
                Material::Lambertian { .. } | Material::Metal { .. } => {
                    panic!("no textures in the final scene")
                }
                Material::Dielectric { ior } => assert_eq!(ior, 1.5),
                Material::Emissive { .. } => panic!("no lights in the final scene"),
            }
        }
    }
}
