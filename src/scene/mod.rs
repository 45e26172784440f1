//! The scene model: what Ray Tracing in One Weekend's scenes need, and nothing more.
//!
//! A [`Scene`] is built-in ([`builtin`]), read from a versioned JSON file ([`load`]) or imported
//! from glTF 2.0 ([`gltf`]); a JSON scene can be written back out ([`export`]) and loaded again
//! unchanged.

pub mod builtin;
pub mod cornell;
pub mod enclosure;
pub mod export;
pub mod gltf;
pub mod heavy;
pub mod image;
pub mod kinds;
pub mod load;
pub mod obj;
pub mod stress;
pub mod terrain;
pub mod texture;
pub mod two_lights;

use glam::{Vec2, Vec3};

pub use crate::input_error::InputError;
pub use image::{Image, ImageSource, Wrap};
pub use texture::{Pattern, Texture};

/// N of a built-in family's name `PREFIX` + N (`spheres-100`, `rtiow-heavy-4`): decimal digits
/// without a leading zero or sign, N in `range`; otherwise `None`, so that each scene has exactly
/// one name.
pub fn family_number(name: &str, prefix: &str, range: std::ops::RangeInclusive<u32>) -> Option<u32> {
    let digits = name.strip_prefix(prefix)?;
    if digits.is_empty() || digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // Long digit strings overflow u32: also out of range.
    let n: u32 = digits.parse().ok()?;
    range.contains(&n).then_some(n)
}

/// The format tag every scene file carries in its `"format"` field.
pub const FORMAT: &str = "wavetrace-scene/1";

/// Camera as in Ray Tracing in One Weekend (4th edition): the image size comes from the render
/// settings, not the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSpec {
    pub lookfrom: Vec3,
    pub lookat: Vec3,
    pub vup: Vec3,
    /// Vertical field of view, degrees.
    pub vfov: f32,
    /// Angle of the defocus cone through each pixel, degrees; 0 is a pinhole.
    pub defocus_angle: f32,
    /// Distance from `lookfrom` to the plane of perfect focus.
    pub focus_dist: f32,
}

/// What a ray that leaves the scene sees.
#[derive(Clone, Debug, PartialEq)]
pub enum Background {
    /// The book's gradient: white at the horizon blending to (0.5, 0.7, 1.0) straight up.
    Sky,
    /// The same radiance in every direction (the furnace test).
    Constant(Vec3),
}

/// The book's four material kinds (the emitter from The Next Week).
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    Lambertian {
        albedo: Texture,
    },
    Metal {
        albedo: Texture,
        fuzz: f32,
    },
    /// Schlick's approximation for reflectance; `ior < 1` models a bubble.
    Dielectric {
        ior: f32,
    },
    /// A light on any primitive: emits `radiance` from both sides and ends the path.
    Emissive {
        radiance: Vec3,
    },
}

impl Material {
    /// The stable name used in scene files, GPU kind ids and reports.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Material::Lambertian { .. } => "lambertian",
            Material::Metal { .. } => "metal",
            Material::Dielectric { .. } => "dielectric",
            Material::Emissive { .. } => "emissive",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct NamedMaterial {
    pub name: String,
    pub material: Material,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// Index into [`Scene::materials`].
    pub material: u32,
}

/// A parallelogram, as in Ray Tracing: The Next Week: `corner + α·u + β·v` for α, β in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    pub corner: Vec3,
    pub u: Vec3,
    pub v: Vec3,
    pub material: u32,
}

/// A triangle mesh: read from an OBJ file, its vertices used as written there, generated, or
/// one primitive of a glTF scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub source: MeshSource,
    pub triangles: Vec<[Vec3; 3]>,
    /// Texture coordinates at each triangle's corners (glTF `TEXCOORD_0`, OBJ `vt`), if the mesh
    /// has them; without, an image is looked up at (0, 0), (1, 0), (0, 1) at the corners, as a
    /// quad's corner, `u` and `v` ends are.
    pub uvs: Option<Vec<[Vec2; 3]>>,
    pub material: u32,
}

/// Where a mesh's triangles come from, as a scene file names it.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshSource {
    /// An OBJ file, absolute, so a scene written back out still finds it (`"file"`).
    File(std::path::PathBuf),
    /// [`terrain::triangles`] of this many triangles, generated (`"terrain"`).
    Terrain(u32),
    /// A primitive of a glTF file (absolute), through its node's transform: `primitive` names
    /// both, e.g. `nodes[3] meshes[0].primitives[1]`. Scene files cannot refer to one.
    Gltf { file: std::path::PathBuf, primitive: String },
}

/// The scene's shapes. A scene file lists them in one `objects` array; here they are grouped by
/// shape, and files written back out list spheres, then quads, then meshes.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A built-in name, or the file's stem.
    pub name: String,
    pub camera: CameraSpec,
    pub background: Background,
    pub materials: Vec<NamedMaterial>,
    pub spheres: Vec<Sphere>,
    pub quads: Vec<Quad>,
    pub meshes: Vec<Mesh>,
    /// The images that [`Texture::Image`] albedos index.
    pub images: Vec<Image>,
}

impl Scene {
    /// Resolves a `--scene` argument: a built-in name, otherwise a path to a scene file.
    pub fn resolve(arg: &str) -> Result<Scene, InputError> {
        if let Some(scene) = builtin::by_name(arg) {
            return Ok(scene);
        }
        let path = std::path::Path::new(arg);
        if !path.exists() {
            return Err(InputError::new(arg, "", builtin::unknown_scene(arg, path)));
        }
        Scene::from_path(path)
    }

    /// Reads a scene file: glTF 2.0 for `.gltf` / `.glb` ([`gltf::read`], its warnings logged),
    /// our JSON format ([`load::from_file`]) otherwise. Every scene path a user gives (`--scene`,
    /// an experiment's `scenes`, `scene info`) is read through here.
    pub fn from_path(path: &std::path::Path) -> Result<Scene, InputError> {
        if gltf::is_gltf_path(path) {
            gltf::read(path).map(|import| import.scene)
        } else {
            load::from_file(path)
        }
    }

    pub fn material(&self, sphere: &Sphere) -> &Material {
        &self.materials[sphere.material as usize].material
    }

    /// Spheres, quads and mesh triangles: what the BVH is built over.
    pub fn primitive_count(&self) -> usize {
        self.spheres.len() + self.quads.len() + self.meshes.iter().map(|m| m.triangles.len()).sum::<usize>()
    }
}
