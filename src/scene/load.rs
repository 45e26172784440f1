//! Scene files: versioned JSON, read strictly.
//!
//! The text is parsed into a [`serde_json::Value`] and then walked by hand rather than derived
//! with serde, so that every error can name the file, the JSON path of the offending value
//! (`objects[3].radius`, `materials.red.albedo[1]`, `camera.vfov`) and a reason a person can act
//! on. The format (`"format": "wavetrace-scene/1"`):
//!
//! ```json
//! {
//!   "format": "wavetrace-scene/1",
//!   "camera": {"lookfrom": [13, 2, 3], "lookat": [0, 0, 0], "vup": [0, 1, 0],
//!              "vfov": 20, "defocus_angle": 0.6, "focus_dist": 10},
//!   "background": {"type": "sky"},
//!   "materials": {
//!     "ground": {"type": "lambertian", "albedo": [0.5, 0.5, 0.5]},
//!     "m": {"type": "metal", "albedo": [0.7, 0.6, 0.5], "fuzz": 0.0},
//!     "g": {"type": "dielectric", "ior": 1.5},
//!     "l": {"type": "emissive", "radiance": [4, 4, 4]}
//!   },
//!   "objects": [
//!     {"type": "sphere", "center": [0, -1000, 0], "radius": 1000, "material": "ground"},
//!     {"type": "quad", "corner": [343, 554, 332], "u": [-130, 0, 0], "v": [0, 0, -105], "material": "l"},
//!     {"type": "mesh", "file": "bunny.obj", "material": "m"}
//!   ]
//! }
//! ```
//! `background` is `{"type": "sky"}` or `{"type": "constant", "color": [r, g, b]}`. A quad is
//! `corner + α·u + β·v` for α, β in [0, 1] (The Next Week's `quad`). A mesh's `file` is an OBJ
//! ([`super::obj`]) whose path is relative to the scene file; its vertices are used as written.
//! An albedo may be an image: `{"type": "image", "file": "wood.png", "wrap": ["repeat",
//! "clamp"], "tint": [1, 1, 1]}`, a PNG relative to the scene file looked up at the surface's
//! texture coordinates (`super::image`; wrap along u then v: `repeat`, `clamp` or `mirror`).
//!
//! Rules:
//! - Every field shown is required; there are no defaults, so a file says everything it means.
//! - Unknown fields are errors (a typo such as `"radus"` must not pass silently), and so are
//!   duplicate keys in any object (plain serde_json would keep the last one without a word).
//! - Numbers are read as f64 and stored as f32; a value that is not finite as an f32 (`1e39`) is
//!   an error.
//! - Materials keep their file order in [`Scene::materials`]; objects name them and store an
//!   index. Unused materials are allowed, and so is an empty `objects` list (the image is then
//!   the background alone).
//! - Value checks (radius > 0, fuzz in [0, 1], a camera that has a view direction, ...) are
//!   [`validate`], which runs on every loaded scene and can be run on scenes built in code.
//!
//! Malformed input of any kind gives an `Err`, never a panic.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::{DVec3, Vec3};
use serde_json::{Map, Value};

use crate::strict_json::{describe, did_you_mean, join, parse_strict, quoted_list};

use super::texture::MAX_OCTAVES;
use super::{
    obj, Background, CameraSpec, Image, InputError, Material, Mesh, MeshSource, NamedMaterial, Quad, Scene,
    Sphere, Texture, Wrap, FORMAT,
};

/// The `format` tags this build reads.
pub const SUPPORTED_FORMATS: &[&str] = &[FORMAT];

/// Material `type`s, in the order error messages list them.
const MATERIAL_TYPES: &[&str] = &["lambertian", "metal", "dielectric", "emissive"];
const BACKGROUND_TYPES: &[&str] = &["sky", "constant"];
const OBJECT_TYPES: &[&str] = &["sphere", "quad", "mesh"];
const TEXTURE_TYPES: &[&str] = &[
    "solid", "checker", "noise", "marble", "wood", "ridged", "warp", "cellular", "crackle", "value", "image",
];
const WRAP_NAMES: &[&str] = &["repeat", "clamp", "mirror"];

/// Below this sine of the angle between a quad's edges it is refused as degenerate: a sliver
/// whose normal f32 cannot resolve.
const MIN_QUAD_SINE: f32 = 1e-6;

/// Below this sine of the angle between `vup` and the view direction the camera basis
/// (`cross(vup, w)`) is too ill-conditioned in f32 to be trusted (about 0.006 degrees).
const MIN_VUP_SINE: f64 = 1e-4;

/// Reads a scene file; the scene is named after the file's stem.
pub fn from_file(path: &Path) -> Result<Scene, InputError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new(&file, "", format!("cannot read the file: {e}")))?;
    let name = path.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let dir = path.parent().unwrap_or(Path::new("."));
    from_str_in(&text, &file, &name, dir)
}

/// Reads a scene from text. `file_label` names the source in errors (a path, or `<string>`);
/// `name` becomes [`Scene::name`]. Mesh files are found relative to the working directory.
pub fn from_str(text: &str, file_label: &str, name: &str) -> Result<Scene, InputError> {
    from_str_in(text, file_label, name, Path::new("."))
}

/// [`from_str`] with mesh files found relative to `dir` (the scene file's folder).
pub fn from_str_in(text: &str, file_label: &str, name: &str, dir: &Path) -> Result<Scene, InputError> {
    let cx = Cx { file: file_label, dir, images: Default::default() };
    let root = parse_strict(text).map_err(|(path, reason)| InputError::new(file_label, path, reason))?;
    let scene = cx.scene(&root, name)?;
    validate(&scene, file_label)?;
    Ok(scene)
}

impl Scene {
    /// Checks the values a scene file may not hold (see [`validate`]); errors name the file as
    /// `<scene NAME>`.
    pub fn validate(&self) -> Result<(), InputError> {
        validate(self, &format!("<scene {}>", self.name))
    }
}

/// Checks what a well-formed scene may still get wrong: non-finite numbers, radius <= 0, a
/// degenerate quad (a zero edge, or parallel edges), an empty mesh, fuzz
/// outside [0, 1], ior <= 0, negative albedo / radiance / background colour, vfov outside
/// (0, 180), defocus_angle outside [0, 180), focus_dist <= 0, lookat == lookfrom, vup zero or
/// parallel to the view direction, empty or duplicate material names, material indices out of
/// range. Paths in the errors are the ones the scene's file would have; `file` labels them.
pub fn validate(scene: &Scene, file: &str) -> Result<(), InputError> {
    check_camera(&scene.camera)
        .and_then(|()| check_background(&scene.background))
        .and_then(|()| check_materials(&scene.materials))
        .and_then(|()| check_objects(scene))
        .and_then(|()| check_meshes(scene))
        .and_then(|()| check_images(scene))
        .map_err(|(path, reason)| InputError::new(file, path, reason))
}

/// A problem's path in the scene file and its reason.
type Problem = (String, String);

fn check_camera(cam: &CameraSpec) -> Result<(), Problem> {
    for (field, v) in [("lookfrom", cam.lookfrom), ("lookat", cam.lookat), ("vup", cam.vup)] {
        if let Some((path, reason)) = check_vec3(&format!("camera.{field}"), v, false) {
            return Err((path, reason));
        }
    }
    let scalar = |field: &str, v: f32, ok: fn(f32) -> bool, rule: &str| {
        // `ok` is only consulted once the value is known to be finite.
        match check_finite(v).or_else(|| (!ok(v)).then(|| format!("{rule}, got {v}"))) {
            Some(reason) => Err((format!("camera.{field}"), reason)),
            None => Ok(()),
        }
    };
    let in_0_180 = |v| v > 0.0 && v < 180.0;
    scalar("vfov", cam.vfov, in_0_180, "must be in (0, 180) degrees")?;
    let angle_ok = |v| (0.0..180.0).contains(&v);
    scalar("defocus_angle", cam.defocus_angle, angle_ok, "must be in [0, 180) degrees")?;
    scalar("focus_dist", cam.focus_dist, |v| v > 0.0, "must be > 0")?;
    // The direction and the up vector are checked in f64 after scaling each to a largest
    // component of 1, so neither huge nor tiny inputs overflow or underflow the test.
    let dir = cam.lookat.as_dvec3() - cam.lookfrom.as_dvec3();
    if dir == DVec3::ZERO {
        return Err((
            "camera.lookat".into(),
            "equals camera.lookfrom, so the camera has no view direction".into(),
        ));
    }
    if cam.vup == Vec3::ZERO {
        return Err(("camera.vup".into(), "must not be the zero vector".into()));
    }
    let (d, u) = (dir / dir.abs().max_element(), cam.vup.as_dvec3() / cam.vup.abs().max_element() as f64);
    let sine = d.cross(u).length() / (d.length() * u.length());
    if sine < MIN_VUP_SINE {
        return Err((
            "camera.vup".into(),
            format!(
                "is parallel (or nearly) to the view direction lookat - lookfrom = {}; \
                 choose an up vector at an angle to it",
                fmt_vec(dir.as_vec3())
            ),
        ));
    }
    Ok(())
}

fn check_background(background: &Background) -> Result<(), Problem> {
    match *background {
        Background::Constant(color) => check_vec3("background.color", color, true).map_or(Ok(()), Err),
        _ => Ok(()),
    }
}

fn check_materials(materials: &[NamedMaterial]) -> Result<(), Problem> {
    let mut seen: HashMap<&str, usize> = HashMap::with_capacity(materials.len());
    for (i, m) in materials.iter().enumerate() {
        if m.name.is_empty() {
            return Err((format!("materials[{i}]"), "material name must not be empty".into()));
        }
        let path = join("materials", &m.name);
        if let Some(first) = seen.insert(&m.name, i) {
            return Err((
                path,
                format!("duplicate material name (materials {first} and {i}); names must be unique"),
            ));
        }
        let problem = match m.material {
            Material::Lambertian { albedo } => check_texture(&format!("{path}.albedo"), &albedo),
            Material::Metal { albedo, fuzz } => {
                check_texture(&format!("{path}.albedo"), &albedo).or_else(|| {
                    let reason = check_finite(fuzz).or_else(|| {
                        (!(0.0..=1.0).contains(&fuzz)).then(|| format!("must be in [0, 1], got {fuzz}"))
                    });
                    reason.map(|r| (format!("{path}.fuzz"), r))
                })
            }
            Material::Dielectric { ior } => check_finite(ior)
                .or_else(|| (ior <= 0.0).then(|| format!("must be > 0, got {ior}")))
                .map(|r| (format!("{path}.ior"), r)),
            Material::Emissive { radiance } => check_vec3(&format!("{path}.radiance"), radiance, true),
        };
        if let Some((path, reason)) = problem {
            return Err((path, reason));
        }
    }
    Ok(())
}

/// Shapes are numbered as a file written by `export` lists them: spheres, quads, meshes.
fn check_objects(scene: &Scene) -> Result<(), Problem> {
    let n_materials = scene.materials.len();
    let material_ok = |path: &str, m: u32| {
        ((m as usize) >= n_materials).then(|| {
            (
                format!("{path}.material"),
                format!("refers to material index {m}, but the scene has {n_materials} materials"),
            )
        })
    };
    let quads = scene.quads.iter().map(|q| (Some(q), q.material));
    let shapes = scene.spheres.iter().map(|s| (None, s.material)).chain(quads);
    let meshes = scene.meshes.iter().map(|m| (None, m.material));
    for (i, (quad, material)) in shapes.chain(meshes).enumerate() {
        let path = format!("objects[{i}]");
        let problem = match (i < scene.spheres.len(), quad) {
            (true, _) => check_sphere(&path, &scene.spheres[i]),
            (false, Some(q)) => check_quad(&path, q),
            (false, None) => None,
        };
        if let Some((path, reason)) = problem.or_else(|| material_ok(&path, material)) {
            return Err((path, reason));
        }
    }
    Ok(())
}

fn check_meshes(scene: &Scene) -> Result<(), Problem> {
    for (k, m) in scene.meshes.iter().enumerate() {
        let path = format!("objects[{}]", scene.spheres.len() + scene.quads.len() + k);
        if m.triangles.is_empty() {
            return Err((format!("{path}.file"), "the mesh has no triangles".into()));
        }
        if let Some(t) = m.triangles.iter().flatten().find(|p| !p.is_finite()) {
            return Err((format!("{path}.file"), format!("a vertex is not finite: {}", fmt_vec(*t))));
        }
        if let Some(uvs) = &m.uvs {
            if uvs.len() != m.triangles.len() {
                return Err((
                    format!("{path}.file"),
                    format!("{} triangles but texture coordinates for {}", m.triangles.len(), uvs.len()),
                ));
            }
            if let Some(uv) = uvs.iter().flatten().find(|uv| !uv.is_finite()) {
                return Err((format!("{path}.file"), format!("a texture coordinate is not finite: {uv}")));
            }
        }
    }
    Ok(())
}

/// Image textures refer to images that exist, and each image holds its texels.
fn check_images(scene: &Scene) -> Result<(), Problem> {
    for (i, m) in scene.materials.iter().enumerate() {
        let (Material::Lambertian { albedo: Texture::Image { image, .. } }
        | Material::Metal { albedo: Texture::Image { image, .. }, .. }) = m.material
        else {
            continue;
        };
        if image as usize >= scene.images.len() {
            return Err((
                format!("{}.albedo", join("materials", &m.name)),
                format!(
                    "refers to image {image}, but the scene has {} images (materials[{i}])",
                    scene.images.len()
                ),
            ));
        }
    }
    for im in &scene.images {
        if im.width == 0
            || im.height == 0
            || im.texels.len() as u64 != u64::from(im.width) * u64::from(im.height)
        {
            return Err((
                "images".into(),
                format!("{}: {}×{} with {} texels", im.source, im.width, im.height, im.texels.len()),
            ));
        }
    }
    Ok(())
}

/// A sphere needs a finite centre and a finite radius > 0.
fn check_sphere(path: &str, s: &Sphere) -> Option<(String, String)> {
    check_vec3(&format!("{path}.center"), s.center, false).or_else(|| {
        check_finite(s.radius)
            .or_else(|| (s.radius <= 0.0).then(|| format!("must be > 0, got {}", s.radius)))
            .map(|r| (format!("{path}.radius"), r))
    })
}

/// A quad needs finite vectors and two edges that span a parallelogram.
fn check_quad(path: &str, q: &Quad) -> Option<(String, String)> {
    let vectors = [("corner", q.corner), ("u", q.u), ("v", q.v)];
    if let Some(p) = vectors.iter().find_map(|(f, v)| check_vec3(&format!("{path}.{f}"), *v, false)) {
        return Some(p);
    }
    for (f, e) in [("u", q.u), ("v", q.v)] {
        if e == Vec3::ZERO {
            return Some((format!("{path}.{f}"), "is the zero vector, so the quad is degenerate".into()));
        }
    }
    // In f64 so that large edges cannot overflow the product.
    let (u, v) = (q.u.as_dvec3(), q.v.as_dvec3());
    if (u.cross(v).length() / (u.length() * v.length())) < MIN_QUAD_SINE as f64 {
        return Some((
            format!("{path}.v"),
            format!("is parallel to u = {} (or nearly), so the quad is degenerate (zero area)", fmt_vec(q.u)),
        ));
    }
    None
}

fn check_finite(x: f32) -> Option<String> {
    (!x.is_finite()).then(|| format!("not a finite number ({x})"))
}

/// The first component of `v` that is not finite, or negative when `non_negative`.
fn check_vec3(path: &str, v: Vec3, non_negative: bool) -> Option<(String, String)> {
    v.to_array().iter().enumerate().find_map(|(i, &c)| {
        let reason =
            check_finite(c).or_else(|| (non_negative && c < 0.0).then(|| format!("must be >= 0, got {c}")));
        reason.map(|r| (format!("{path}[{i}]"), r))
    })
}

/// A texture's colours must be finite and non-negative, its scale finite and > 0, its octaves in
/// 1..=MAX_OCTAVES. Paths are those of the scene file (`materials.m.albedo.octaves`).
fn check_texture(path: &str, t: &Texture) -> Option<(String, String)> {
    let positive = |field: &str, x: f32| {
        check_finite(x)
            .or_else(|| (x <= 0.0).then(|| format!("must be > 0, got {x}")))
            .map(|r| (format!("{path}.{field}"), r))
    };
    let octaves_ok = |n: u32| {
        (!(1..=MAX_OCTAVES).contains(&n))
            .then(|| (format!("{path}.octaves"), format!("must be in 1..={MAX_OCTAVES}, got {n}")))
    };
    match *t {
        Texture::Solid(c) => check_vec3(path, c, true),
        Texture::Checker { scale, even, odd } => positive("scale", scale)
            .or_else(|| check_vec3(&format!("{path}.even"), even, true))
            .or_else(|| check_vec3(&format!("{path}.odd"), odd, true)),
        Texture::Procedural { scale, octaves, color, .. } => positive("scale", scale)
            .or_else(|| octaves_ok(octaves))
            .or_else(|| check_vec3(&format!("{path}.color"), color, true)),
        Texture::Image { tint, .. } => check_vec3(&format!("{path}.tint"), tint, true),
    }
}

fn fmt_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

// ---------------------------------------------------------------------------------------------
// Walking the Value into the model.

type Res<T> = Result<T, InputError>;

/// The walk's context: the file label every error carries.
struct Cx<'a> {
    file: &'a str,
    /// Where relative mesh and image paths start.
    dir: &'a Path,
    /// The images read so far, each file once.
    images: std::cell::RefCell<Vec<Image>>,
}

/// A JSON object being read: its fields, its path, and the fields it may have.
struct Obj<'v> {
    map: &'v Map<String, Value>,
    path: String,
}

impl Cx<'_> {
    fn err<T>(&self, path: &str, reason: impl Into<String>) -> Res<T> {
        Err(InputError::new(self.file, path, reason))
    }

    fn scene(&self, root: &Value, name: &str) -> Res<Scene> {
        let root = self.object(root, "")?;
        // The version is checked before anything else, so a newer file is reported as newer
        // rather than as a list of unknown fields.
        let Some(format) = root.map.get("format") else {
            return self
                .err("", format!("missing required field \"format\" (expected \"format\": \"{FORMAT}\")"));
        };
        let format = self.string(format, "format")?;
        if !SUPPORTED_FORMATS.contains(&format) {
            return self.err(
                "format",
                format!("unsupported format {format:?}; this build reads {}", quoted_list(SUPPORTED_FORMATS)),
            );
        }
        self.only(&root, &["format", "camera", "background", "materials", "objects"])?;

        let camera = self.camera(&root)?;
        let background = self.background(&root)?;
        let materials = self.materials(&root)?;
        let (spheres, quads, meshes) = self.objects(&root, &materials)?;
        let images = self.images.take();
        Ok(Scene { name: name.to_owned(), camera, background, materials, spheres, quads, meshes, images })
    }

    fn camera(&self, root: &Obj) -> Res<CameraSpec> {
        let (v, path) = self.field(root, "camera")?;
        let o = self.object(v, &path)?;
        self.only(&o, &["lookfrom", "lookat", "vup", "vfov", "defocus_angle", "focus_dist"])?;
        Ok(CameraSpec {
            lookfrom: self.vec3_field(&o, "lookfrom")?,
            lookat: self.vec3_field(&o, "lookat")?,
            vup: self.vec3_field(&o, "vup")?,
            vfov: self.number_field(&o, "vfov")?,
            defocus_angle: self.number_field(&o, "defocus_angle")?,
            focus_dist: self.number_field(&o, "focus_dist")?,
        })
    }

    fn background(&self, root: &Obj) -> Res<Background> {
        let (v, path) = self.field(root, "background")?;
        let o = self.object(v, &path)?;
        match self.type_field(&o, "background", BACKGROUND_TYPES)? {
            "sky" => {
                self.only(&o, &["type"])?;
                Ok(Background::Sky)
            }
            _ => {
                self.only(&o, &["type", "color"])?;
                Ok(Background::Constant(self.vec3_field(&o, "color")?))
            }
        }
    }

    fn materials(&self, root: &Obj) -> Res<Vec<NamedMaterial>> {
        let (v, path) = self.field(root, "materials")?;
        let all = self.object(v, &path)?;
        let mut out = Vec::with_capacity(all.map.len());
        for (name, v) in all.map {
            let path = join(&all.path, name);
            if name.is_empty() {
                return self.err(&path, "material name must not be empty");
            }
            let o = self.object(v, &path)?;
            let material = match self.type_field(&o, "material", MATERIAL_TYPES)? {
                "lambertian" => {
                    self.only(&o, &["type", "albedo"])?;
                    Material::Lambertian { albedo: self.texture_field(&o, "albedo")? }
                }
                "metal" => {
                    self.only(&o, &["type", "albedo", "fuzz"])?;
                    Material::Metal {
                        albedo: self.texture_field(&o, "albedo")?,
                        fuzz: self.number_field(&o, "fuzz")?,
                    }
                }
                "dielectric" => {
                    self.only(&o, &["type", "ior"])?;
                    Material::Dielectric { ior: self.number_field(&o, "ior")? }
                }
                _ => {
                    self.only(&o, &["type", "radiance"])?;
                    Material::Emissive { radiance: self.vec3_field(&o, "radiance")? }
                }
            };
            out.push(NamedMaterial { name: name.clone(), material });
        }
        Ok(out)
    }

    fn objects(&self, root: &Obj, materials: &[NamedMaterial]) -> Res<(Vec<Sphere>, Vec<Quad>, Vec<Mesh>)> {
        let (v, path) = self.field(root, "objects")?;
        let Value::Array(items) = v else {
            return self.err(&path, format!("expected an array of objects, found {}", describe(v)));
        };
        let index: HashMap<&str, u32> =
            materials.iter().enumerate().map(|(i, m)| (m.name.as_str(), i as u32)).collect();
        let (mut spheres, mut quads, mut meshes) = (Vec::new(), Vec::new(), Vec::new());
        for (i, v) in items.iter().enumerate() {
            let o = self.object(v, &format!("{path}[{i}]"))?;
            let kind = self.type_field(&o, "object", OBJECT_TYPES)?;
            let material = |o: &Obj| -> Res<u32> {
                let (mv, mpath) = self.field(o, "material")?;
                let mname = self.string(mv, &mpath)?;
                match index.get(mname) {
                    Some(&m) => Ok(m),
                    None => self.err(&mpath, unknown_material(mname, materials)),
                }
            };
            // Value checks run here, where the object's index in the file is known; `validate`
            // repeats them on the grouped shapes.
            let problem = match kind {
                "sphere" => {
                    self.only(&o, &["type", "center", "radius", "material"])?;
                    let center = self.vec3_field(&o, "center")?;
                    let radius = self.number_field(&o, "radius")?;
                    let s = Sphere { center, radius, material: material(&o)? };
                    spheres.push(s);
                    check_sphere(&o.path, &s)
                }
                "quad" => {
                    self.only(&o, &["type", "corner", "u", "v", "material"])?;
                    let q = Quad {
                        corner: self.vec3_field(&o, "corner")?,
                        u: self.vec3_field(&o, "u")?,
                        v: self.vec3_field(&o, "v")?,
                        material: material(&o)?,
                    };
                    quads.push(q);
                    check_quad(&o.path, &q)
                }
                _ if o.map.contains_key("terrain") => {
                    self.only(&o, &["type", "terrain", "material"])?;
                    let (tv, tpath) = self.field(&o, "terrain")?;
                    let n = self.terrain_size(tv, &tpath)?;
                    let triangles = super::terrain::triangles(n);
                    meshes.push(Mesh {
                        source: MeshSource::Terrain(n),
                        triangles,
                        uvs: None,
                        material: material(&o)?,
                    });
                    None
                }
                _ => {
                    self.only(&o, &["type", "file", "material"])?;
                    let (fv, fpath) = self.field(&o, "file")?;
                    let name = self.string(fv, &fpath)?;
                    let file = std::path::absolute(self.dir.join(name))
                        .map_err(|e| InputError::new(self.file, &fpath, format!("bad path {name:?}: {e}")))?;
                    let mesh = obj::read(&file).map_err(|e| InputError::new(self.file, &fpath, e))?;
                    if mesh.degenerate > 0 {
                        log::warn!(
                            "{}: {fpath}: dropped {} zero-area triangles of {}",
                            self.file,
                            mesh.degenerate,
                            mesh.degenerate + mesh.triangles.len()
                        );
                    }
                    if let Some(note) = &mesh.uv_note {
                        log::warn!("{}: {fpath}: {note}", self.file);
                    }
                    meshes.push(Mesh {
                        source: MeshSource::File(file),
                        triangles: mesh.triangles,
                        uvs: mesh.uvs,
                        material: material(&o)?,
                    });
                    None
                }
            };
            if let Some((path, reason)) = problem {
                return self.err(&path, reason);
            }
        }
        Ok((spheres, quads, meshes))
    }

    // -- Field helpers ----------------------------------------------------------------------

    fn object<'v>(&self, v: &'v Value, path: &str) -> Res<Obj<'v>> {
        match v {
            Value::Object(map) => Ok(Obj { map, path: path.to_owned() }),
            _ => self.err(path, format!("expected an object, found {}", describe(v))),
        }
    }

    /// A required field and its path.
    fn field<'v>(&self, o: &Obj<'v>, key: &str) -> Res<(&'v Value, String)> {
        match o.map.get(key) {
            Some(v) => Ok((v, join(&o.path, key))),
            None => self.err(&o.path, format!("missing required field \"{key}\"")),
        }
    }

    /// Rejects fields outside `allowed`, naming the first unknown one.
    fn only(&self, o: &Obj, allowed: &[&str]) -> Res<()> {
        match o.map.keys().find(|k| !allowed.contains(&k.as_str())) {
            None => Ok(()),
            Some(k) => self.err(
                &join(&o.path, k),
                format!("unknown field{}; expected {}", did_you_mean(k, allowed), quoted_list(allowed)),
            ),
        }
    }

    /// The `type` field of a tagged object, which must be one of `types`.
    fn type_field<'v>(&self, o: &Obj<'v>, what: &str, types: &[&'static str]) -> Res<&'static str> {
        let (v, path) = self.field(o, "type")?;
        let t = self.string(v, &path)?;
        match types.iter().find(|&&known| known == t) {
            Some(&known) => Ok(known),
            None => self.err(
                &path,
                format!(
                    "unknown {what} type {t:?}{}; expected {}",
                    did_you_mean(t, types),
                    quoted_list(types)
                ),
            ),
        }
    }

    /// A mesh's `terrain`: its triangle count, 1..=`terrain::TRIANGLES_MAX`.
    fn terrain_size(&self, v: &Value, path: &str) -> Res<u32> {
        let max = super::terrain::TRIANGLES_MAX;
        match v.as_u64() {
            Some(n) if (1..=max as u64).contains(&n) => Ok(n as u32),
            _ => self.err(path, format!("expected a triangle count in 1..={max}, found {}", describe(v))),
        }
    }

    fn string<'v>(&self, v: &'v Value, path: &str) -> Res<&'v str> {
        match v {
            Value::String(s) => Ok(s),
            _ => self.err(path, format!("expected a string, found {}", describe(v))),
        }
    }

    fn number(&self, v: &Value, path: &str) -> Res<f32> {
        let Some(x) = v.as_f64() else {
            return self.err(path, format!("expected a number, found {}", describe(v)));
        };
        let y = x as f32;
        if !y.is_finite() {
            return self.err(path, format!("not a finite number: {x:e} is outside the f32 range"));
        }
        Ok(y)
    }

    fn number_field(&self, o: &Obj, key: &str) -> Res<f32> {
        let (v, path) = self.field(o, key)?;
        self.number(v, &path)
    }

    /// An albedo: `[r, g, b]`, or a texture object `{"type": "solid" | "checker" | "noise" |
    /// "marble" | "wood" | "ridged" | "warp" | "cellular" | "crackle" | "value", ...}`.
    fn texture_field(&self, o: &Obj, key: &str) -> Res<Texture> {
        let (v, path) = self.field(o, key)?;
        if !v.is_object() {
            return Ok(Texture::Solid(self.vec3_field(o, key)?));
        }
        let t = self.object(v, &path)?;
        Ok(match self.type_field(&t, "texture", TEXTURE_TYPES)? {
            "solid" => {
                self.only(&t, &["type", "color"])?;
                Texture::Solid(self.vec3_field(&t, "color")?)
            }
            "checker" => {
                self.only(&t, &["type", "scale", "even", "odd"])?;
                Texture::Checker {
                    scale: self.number_field(&t, "scale")?,
                    even: self.vec3_field(&t, "even")?,
                    odd: self.vec3_field(&t, "odd")?,
                }
            }
            "image" => {
                self.only(&t, &["type", "file", "wrap", "tint"])?;
                let image = self.image_file(&t)?;
                let (wv, wpath) = self.field(&t, "wrap")?;
                let wrap = match wv {
                    Value::Array(a) if a.len() == 2 => {
                        let mut out = [Wrap::Repeat; 2];
                        for (i, (w, v)) in out.iter_mut().zip(a).enumerate() {
                            let path = format!("{wpath}[{i}]");
                            let name = self.string(v, &path)?;
                            *w = Wrap::from_name(name).ok_or_else(|| {
                                InputError::new(
                                    self.file,
                                    &path,
                                    format!(
                                        "unknown wrap {name:?}{}; expected {}",
                                        did_you_mean(name, WRAP_NAMES),
                                        quoted_list(WRAP_NAMES)
                                    ),
                                )
                            })?;
                        }
                        out
                    }
                    _ => {
                        return self.err(
                            &wpath,
                            format!(
                                "expected [u, v] wraps, each of {}, found {}",
                                quoted_list(WRAP_NAMES),
                                describe(wv)
                            ),
                        )
                    }
                };
                Texture::Image { image, wrap, tint: self.vec3_field(&t, "tint")? }
            }
            kind => {
                self.only(&t, &["type", "scale", "octaves", "color"])?;
                let scale = self.number_field(&t, "scale")?;
                let (ov, opath) = self.field(&t, "octaves")?;
                let octaves = match ov.as_u64() {
                    Some(n) if n <= u32::MAX as u64 => n as u32,
                    _ => return self.err(&opath, format!("expected a whole number, found {}", describe(ov))),
                };
                let color = self.vec3_field(&t, "color")?;
                let pattern = super::Pattern::from_name(kind).expect("TEXTURE_TYPES lists the patterns");
                Texture::Procedural { pattern, scale, octaves, color }
            }
        })
    }

    /// An image texture's `file`: a PNG relative to the scene file, read once however many
    /// materials name it; its index in the scene's images.
    fn image_file(&self, t: &Obj) -> Res<u32> {
        let (fv, fpath) = self.field(t, "file")?;
        let name = self.string(fv, &fpath)?;
        let file = std::path::absolute(self.dir.join(name))
            .map_err(|e| InputError::new(self.file, &fpath, format!("bad path {name:?}: {e}")))?;
        let mut images = self.images.borrow_mut();
        let known =
            images.iter().position(|im| matches!(&im.source, super::ImageSource::File(f) if *f == file));
        if let Some(i) = known {
            return Ok(i as u32);
        }
        let image = Image::read_png(&file).map_err(|e| InputError::new(self.file, &fpath, e))?;
        images.push(image);
        Ok(images.len() as u32 - 1)
    }

    fn vec3_field(&self, o: &Obj, key: &str) -> Res<Vec3> {
        let (v, path) = self.field(o, key)?;
        match v {
            Value::Array(a) if a.len() == 3 => {
                let mut out = [0.0; 3];
                for (i, (x, c)) in out.iter_mut().zip(a).enumerate() {
                    *x = self.number(c, &format!("{path}[{i}]"))?;
                }
                Ok(Vec3::from_array(out))
            }
            _ => self.err(&path, format!("expected an array of 3 numbers, found {}", describe(v))),
        }
    }
}

/// The reason for an object naming a material the file does not define.
fn unknown_material(name: &str, materials: &[NamedMaterial]) -> String {
    const SHOWN: usize = 8;
    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    let mut s = format!("unknown material {name:?}{}; ", did_you_mean(name, &names));
    if names.is_empty() {
        s.push_str("the file defines no materials");
    } else {
        let shown: Vec<String> = names.iter().take(SHOWN).map(|n| format!("{n:?}")).collect();
        let _ = write!(s, "defined materials: {}", shown.join(", "));
        if names.len() > SHOWN {
            let _ = write!(s, " and {} more", names.len() - SHOWN);
        }
    }
    s
}
