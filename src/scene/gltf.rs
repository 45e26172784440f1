//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, `.glb`), mapped onto the book's
//! materials. The rule, which docs/cli-and-configs.md#gltf-scenes tabulates:
//!
//! - Geometry: every primitive of every mesh reached from the default scene's nodes (scene 0
//!   when none is marked), positions taken through the node's world matrix. Triangle lists,
//!   strips and fans become triangles; points and lines are skipped with a warning.
//! - Camera: the first perspective camera in the node hierarchy (depth first, in file order),
//!   looking down its node's −Z with +Y up; `yfov` becomes `vfov`, a pinhole. With none, a camera
//!   framing the scene's bounds (with a warning).
//! - Materials, first match: emissive (`emissiveFactor` × `KHR_materials_emissive_strength`) >
//!   0 → emissive; `KHR_materials_transmission` ≥ 0.5 → dielectric with `KHR_materials_ior`
//!   (1.5 when absent); `metallicFactor` ≥ 0.5 → metal, albedo `baseColorFactor`, fuzz
//!   `roughnessFactor`; otherwise lambertian with albedo `baseColorFactor`. A primitive without
//!   a material gets glTF's default (white, metallic 1, roughness 1), so a metal.
//! - Textures: a lambertian's or metal's `baseColorTexture` (PNG; a JPEG is dropped with a
//!   warning) becomes an image albedo tinted by `baseColorFactor`, looked up at the primitive's
//!   `TEXCOORD_0` (another `texCoord` is warned about and read as 0) with the sampler's
//!   `wrapS` / `wrapT`, bilinear whatever its filters (`super::image`). A textured primitive
//!   without `TEXCOORD_0` gets the default corners, (0, 0), (1, 0), (0, 1), with a warning.
//!   `KHR_texture_transform` and the other texture slots are ignored with a warning.
//! - Background: the sky gradient (glTF has none).
//!
//! Whatever the rule drops is named in a warning ([`Import::warnings`], each also logged), and
//! a malformed file is an [`InputError`] naming the file, the glTF JSON path and the reason.

use std::path::{Path, PathBuf};

use ::gltf as g;
use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3};

use super::{
    Background, CameraSpec, Image, ImageSource, InputError, Material, Mesh, MeshSource, NamedMaterial, Scene,
    Texture, Wrap,
};

type Res<T> = Result<T, InputError>;

/// The threshold on `metallicFactor` and on the transmission factor: glTF blends; the book's
/// materials are one kind each.
const KIND_THRESHOLD: f32 = 0.5;

/// Vertical field of view of the camera made when the file has none (the book's 20 crops too
/// tightly for a scene framed by its bounding sphere).
const DEFAULT_VFOV: f32 = 40.0;

/// The extensions the mapping reads; any other in `extensionsUsed` is named in a warning.
const MAPPED_EXTENSIONS: &[&str] =
    &["KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission"];

/// A glTF file read as a scene, and an account of the mapping (`wavetrace scene info`).
#[derive(Clone, Debug)]
pub struct Import {
    pub scene: Scene,
    /// One line per glTF object that became part of the scene, e.g.
    /// `materials[0] "red" → lambertian, albedo [0.8, 0.1, 0.1]`.
    pub mapped: Vec<String>,
    /// What could not be mapped, each naming the glTF object and field.
    pub warnings: Vec<String>,
}

/// Whether `path` names a glTF file (`.gltf` or `.glb`, any case).
pub fn is_gltf_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Reads a glTF file; the scene is named after the file's stem, external buffers and images
/// are found relative to its folder. Warnings are logged as well as returned.
pub fn read(path: &Path) -> Res<Import> {
    let import = read_unlogged(path)?;
    for w in &import.warnings {
        log::warn!("{}: {w}", path.display());
    }
    Ok(import)
}

/// [`read`] without logging the warnings: for a caller that prints them itself (`scene info`),
/// so that each is shown once.
pub fn read_unlogged(path: &Path) -> Res<Import> {
    let file = path.display().to_string();
    let bytes =
        std::fs::read(path).map_err(|e| InputError::new(&file, "", format!("cannot read the file: {e}")))?;
    let name = path.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let dir = path.parent().unwrap_or(Path::new("."));
    let source = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    from_slice(&bytes, &file, &name, dir, &source)
}

/// glTF 1.0 is another format (techniques, shaders, objects keyed by id) that the crate reads
/// past with warnings: refused, so nothing half-read is rendered.
fn require_version_2(file: &str, version: &str) -> Res<()> {
    if version.starts_with("2.") {
        return Ok(());
    }
    Err(InputError::new(
        file,
        "asset.version",
        format!("{version:?}: only glTF 2.x is read (a glTF 1.0 asset is a different format; convert it to 2.0 first)"),
    ))
}

/// Reads glTF or GLB bytes. `file` labels errors; `dir` is where relative URIs are found;
/// `source` is recorded in each mesh's [`MeshSource::Gltf`].
pub fn from_slice(bytes: &[u8], file: &str, name: &str, dir: &Path, source: &Path) -> Res<Import> {
    let g::Gltf { document, blob } =
        g::Gltf::from_slice_without_validation(bytes).map_err(|e| crate_error(file, e))?;
    let root = document.into_json();
    require_version_2(file, &root.asset.version)?;
    check_position_indices(file, &root)?;
    let document = g::Document::from_json(root).map_err(|e| crate_error(file, e))?;
    let mut cx = Cx {
        file,
        dir,
        source,
        doc: &document,
        buffers: Vec::new(),
        mapped: Vec::new(),
        warnings: Vec::new(),
        images: Vec::new(),
        image_slots: Default::default(),
    };
    cx.buffers = cx.buffers(blob)?;
    cx.unmapped_extensions();

    let Some(g_scene) = document.default_scene().or_else(|| document.scenes().next()) else {
        return cx.err("scenes", "the file has no scenes, so nothing to render");
    };
    cx.warn_unrendered(&g_scene);
    let (mut materials, default_material) = cx.materials()?;
    let (meshes, camera) = cx.nodes(&g_scene, &mut materials, default_material)?;
    if meshes.is_empty() {
        return cx.err(
            &format!("scenes[{}]", g_scene.index()),
            "reaches no triangles (no node with a mesh of triangle primitives)",
        );
    }

    let camera = camera.unwrap_or_else(|| cx.framing_camera(&meshes));
    cx.mapped.push("background → sky (glTF has no background)".into());
    let scene = Scene {
        name: name.to_owned(),
        camera,
        background: Background::Sky,
        materials,
        spheres: Vec::new(),
        quads: Vec::new(),
        meshes,
        images: cx.images,
    };
    super::load::validate(&scene, file)?;
    Ok(Import { scene, mapped: cx.mapped, warnings: cx.warnings })
}

/// The crate's validation indexes `accessors` with each POSITION unchecked (a panic on a bad
/// index), so those indices are checked first.
fn check_position_indices(file: &str, root: &g::json::Root) -> Res<()> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = prim.attributes.get(&g::json::validation::Checked::Valid(g::Semantic::Positions));
            if let Some(a) = position.filter(|a| a.value() >= root.accessors.len()) {
                return Err(InputError::new(
                    file,
                    format!("meshes[{m}].primitives[{p}].attributes.POSITION"),
                    format!("Index out of range: accessor {} of {}", a.value(), root.accessors.len()),
                ));
            }
        }
    }
    Ok(())
}

struct Cx<'a> {
    file: &'a str,
    dir: &'a Path,
    /// The file, absolute, as meshes and images record it.
    source: &'a Path,
    doc: &'a g::Document,
    buffers: Vec<Vec<u8>>,
    mapped: Vec<String>,
    warnings: Vec<String>,
    /// The scene's images, and each glTF image's index among them (`None`: a JPEG, not decoded).
    images: Vec<Image>,
    image_slots: std::collections::HashMap<usize, Option<u32>>,
}

impl Cx<'_> {
    fn err<T>(&self, path: &str, reason: impl Into<String>) -> Res<T> {
        Err(InputError::new(self.file, path, reason))
    }

    fn warn(&mut self, w: String) {
        self.warnings.push(w);
    }

    fn unmapped_extensions(&mut self) {
        let unmapped: Vec<String> = self
            .doc
            .extensions_used()
            .filter(|e| !MAPPED_EXTENSIONS.contains(e))
            .map(str::to_owned)
            .collect();
        for e in unmapped {
            self.warn(format!("extensionsUsed: {e} is not mapped; whatever it adds is ignored"));
        }
    }

    /// Every buffer's bytes: the GLB's binary chunk, a base64 data URI or a file.
    fn buffers(&self, blob: Option<Vec<u8>>) -> Res<Vec<Vec<u8>>> {
        let mut blob = blob;
        let mut out = Vec::with_capacity(self.doc.buffers().len());
        for b in self.doc.buffers() {
            let path = format!("buffers[{}]", b.index());
            let data =
                match b.source() {
                    g::buffer::Source::Bin => match blob.take() {
                        Some(data) => data,
                        None => return self.err(
                            &path,
                            "has no \"uri\", so it is a GLB's binary chunk, but the file has no binary chunk",
                        ),
                    },
                    g::buffer::Source::Uri(uri) => self
                        .uri_bytes(uri)
                        .map_err(|r| InputError::new(self.file, format!("{path}.uri"), r))?,
                };
            if data.len() < b.length() {
                return self.err(
                    &format!("{path}.byteLength"),
                    format!("is {}, but the buffer's data has only {} bytes", b.length(), data.len()),
                );
            }
            out.push(data);
        }
        Ok(out)
    }

    /// The bytes a URI names: a base64 `data:` URI, or a file relative to the glTF's folder.
    fn uri_bytes(&self, uri: &str) -> Result<Vec<u8>, String> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let Some((meta, data)) = rest.split_once(',') else {
                return Err("a data URI without a comma before its data".into());
            };
            if !meta.ends_with(";base64") {
                return Err(format!(
                    "data URI {meta:?} is not base64-encoded (only base64 data URIs are read)"
                ));
            }
            return base64::engine::general_purpose::STANDARD
                .decode(data)
                .map_err(|e| format!("the data URI's base64 is malformed: {e}"));
        }
        if uri.contains("://") {
            return Err(format!("{uri:?}: only relative file paths and data URIs are read"));
        }
        let file: PathBuf = self.dir.join(percent_decode(uri));
        std::fs::read(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))
    }

    /// Checks that `accessor` can be read as `what` (its types and its byte range), so the
    /// crate's reader (which asserts types and slices unchecked in places) never panics.
    fn check_accessor(
        &self,
        a: &g::Accessor,
        path: &str,
        types: &[g::accessor::DataType],
        dims: g::accessor::Dimensions,
        integers_normalized: bool,
    ) -> Res<()> {
        let id = format!("accessors[{}]", a.index());
        // Integer texture coordinates are normalized (glTF 2.0 §3.7.2.1); indices are not.
        let want_normalized = integers_normalized && a.data_type() != g::accessor::DataType::F32;
        if !types.contains(&a.data_type()) || a.dimensions() != dims || a.normalized() != want_normalized {
            let names: Vec<String> = types.iter().map(|t| format!("{t:?}")).collect();
            return self.err(
                path,
                format!(
                    "{id} is {:?} {:?}{}; expected {dims:?} of {}{}",
                    a.dimensions(),
                    a.data_type(),
                    if a.normalized() { " (normalized)" } else { "" },
                    names.join(" or "),
                    if integers_normalized { " (integers normalized)" } else { "" }
                ),
            );
        }
        if a.count() == 0 {
            return self.err(path, format!("{id} has count 0"));
        }
        if a.sparse().is_some() {
            return self.err(path, format!("{id} is sparse, which this importer does not read"));
        }
        let Some(view) = a.view() else {
            return self.err(path, format!("{id} has no bufferView (all zeros), so no geometry"));
        };
        let size = a.size();
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return self.err(
                path,
                format!(
                    "bufferViews[{}].byteStride {stride} is less than {id}'s element size {size}",
                    view.index()
                ),
            );
        }
        let end = (a.count() - 1).checked_mul(stride).and_then(|n| n.checked_add(a.offset() + size));
        if end.is_none_or(|end| end > view.length()) {
            return self.err(
                path,
                format!(
                    "{id} ({} elements from byte {}, stride {stride}) reads past the end of bufferViews[{}] ({} bytes)",
                    a.count(),
                    a.offset(),
                    view.index(),
                    view.length()
                ),
            );
        }
        self.view_bytes(&view).map(|_| ()).map_err(|r| InputError::new(self.file, path, r))
    }

    /// A buffer view's bytes, checked to lie in its buffer.
    fn view_bytes(&self, view: &g::buffer::View) -> Result<&[u8], String> {
        let buffer = &self.buffers[view.buffer().index()];
        view.offset().checked_add(view.length()).and_then(|end| buffer.get(view.offset()..end)).ok_or_else(
            || {
                format!(
                    "bufferViews[{}] (bytes {}..+{}) lies outside buffers[{}] ({} bytes)",
                    view.index(),
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    buffer.len()
                )
            },
        )
    }

    /// Every glTF material mapped, in file order, and the index glTF's default material will
    /// take if a primitive needs it.
    /// Warns of what the file holds and is not rendered: other scenes, animations.
    fn warn_unrendered(&mut self, g_scene: &g::Scene) {
        let document = self.doc;
        if document.scenes().len() > 1 {
            self.warn(format!(
                "scenes: only scenes[{}] is rendered; the file has {} scenes",
                g_scene.index(),
                document.scenes().len()
            ));
        }
        if document.animations().len() > 0 {
            self.warn(format!(
                "animations: {} animations ignored; nodes are taken at rest",
                document.animations().len()
            ));
        }
    }

    /// The scene's meshes in world space and its camera (the first perspective one).
    fn nodes(
        &mut self,
        g_scene: &g::Scene,
        materials: &mut Vec<NamedMaterial>,
        default_material: u32,
    ) -> Res<(Vec<Mesh>, Option<CameraSpec>)> {
        let mut meshes = Vec::new();
        let mut camera = None;
        // Depth first, in file order, with an explicit stack: a deep hierarchy must not overflow
        // ours, and a node reached twice (a cycle, or two parents, which glTF forbids) is an error.
        let mut seen = vec![false; self.doc.nodes().len()];
        let mut stack: Vec<(g::Node, Mat4)> = g_scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
        stack.reverse();
        while let Some((node, parent)) = stack.pop() {
            let path = format!("nodes[{}]", node.index());
            if std::mem::replace(&mut seen[node.index()], true) {
                return self
                    .err(&path, "is reached twice from the scene (a cycle, or a node with two parents)");
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if !world.is_finite() {
                return self.err(&path, "its world transform is not finite");
            }
            if let Some(c) = node.camera() {
                self.camera(&c, &path, world, &mut camera)?;
            }
            if let Some(mesh) = node.mesh() {
                let m = self.mesh(&mesh, &path, world, self.source, materials, default_material)?;
                meshes.extend(m);
            }
            if node.skin().is_some() {
                self.warn(format!("{path}.skin: skinning ignored; the mesh is taken in its bind pose"));
            }
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, world));
            }
        }
        Ok((meshes, camera))
    }

    /// Where the file has no perspective camera: one that frames the meshes' bounds.
    fn framing_camera(&mut self, meshes: &[Mesh]) -> CameraSpec {
        let c = framing_camera(meshes);
        self.warn(format!(
            "cameras: no perspective camera in the scene; using one that frames its bounds: lookfrom {}, \
             lookat {}, vfov {DEFAULT_VFOV}",
            fmt_vec(c.lookfrom),
            fmt_vec(c.lookat)
        ));
        c
    }

    fn materials(&mut self) -> Res<(Vec<NamedMaterial>, u32)> {
        let mut out: Vec<NamedMaterial> = Vec::new();
        let mut names = std::collections::HashSet::new();
        for m in self.doc.materials() {
            let i = m.index().unwrap_or(0);
            let path = format!("materials[{i}]");
            let material = self.material(&m, &path)?;
            // Scene materials need unique, non-empty names; glTF names need neither.
            let mut name =
                m.name().filter(|n| !n.is_empty()).map_or_else(|| format!("material{i}"), str::to_owned);
            if !names.insert(name.clone()) {
                name = format!("{name}#{i}");
                names.insert(name.clone());
            }
            self.mapped.push(format!("{path} {name:?} → {}", describe(&material)));
            out.push(NamedMaterial { name, material });
        }
        Ok((out, self.doc.materials().len() as u32))
    }

    fn material(&mut self, m: &g::Material, path: &str) -> Res<Material> {
        let pbr = m.pbr_metallic_roughness();
        let ppath = format!("{path}.pbrMetallicRoughness");
        let [r, gr, b, _] = pbr.base_color_factor();
        let base = Vec3::new(r, gr, b);
        if !base.is_finite() || base.min_element() < 0.0 {
            return self.err(
                &format!("{ppath}.baseColorFactor"),
                format!("must be finite and ≥ 0, got {}", fmt_vec(base)),
            );
        }
        let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
        for (field, v) in [("metallicFactor", metallic), ("roughnessFactor", roughness)] {
            if !(0.0..=1.0).contains(&v) {
                return self.err(&format!("{ppath}.{field}"), format!("must be in [0, 1], got {v}"));
            }
        }
        let image = self.base_color_texture(&pbr, &ppath)?;
        let emissive = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        if !emissive.is_finite() || emissive.min_element() < 0.0 {
            return self.err(
                &format!("{path}.emissiveFactor"),
                format!("emission must be finite and ≥ 0, got {}", fmt_vec(emissive)),
            );
        }
        let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
        let ior = m.ior().unwrap_or(1.5);
        if !(ior.is_finite() && ior > 0.0) {
            return self
                .err(&format!("{path}.extensions.KHR_materials_ior.ior"), format!("must be > 0, got {ior}"));
        }

        let material = if emissive.max_element() > 0.0 {
            // A black, opaque emitter loses nothing; any other also reflects or transmits in glTF.
            if base != Vec3::ZERO || transmission > 0.0 {
                self.warn(format!(
                    "{path}: emissive, so it only emits: its reflection (base colour {}, metallic, \
                     roughness, transmission) is dropped (the book's lights do not reflect)",
                    fmt_vec(base)
                ));
            }
            Material::Emissive { radiance: emissive }
        } else if transmission >= KIND_THRESHOLD {
            if base != Vec3::ONE {
                self.warn(format!(
                    "{ppath}.baseColorFactor: tint {} ignored: dielectrics are clear",
                    fmt_vec(base)
                ));
            }
            if roughness > 0.0 {
                self.warn(format!("{ppath}.roughnessFactor: {roughness} ignored: dielectrics are smooth"));
            }
            Material::Dielectric { ior }
        } else if metallic >= KIND_THRESHOLD {
            Material::Metal { albedo: albedo(base, image), fuzz: roughness }
        } else {
            Material::Lambertian { albedo: albedo(base, image) }
        };
        if image.is_some() && matches!(material, Material::Emissive { .. } | Material::Dielectric { .. }) {
            self.warn(format!(
                "{ppath}.baseColorTexture: ignored: the material is {}, which has no albedo",
                material.kind_name()
            ));
        }
        self.warn_unmapped(m, &material, path);
        Ok(material)
    }

    /// The image albedo, if the base colour has a decodable texture: (image, wraps).
    fn base_color_texture(
        &mut self,
        pbr: &g::material::PbrMetallicRoughness,
        ppath: &str,
    ) -> Res<Option<(u32, [Wrap; 2])>> {
        let Some(info) = pbr.base_color_texture() else {
            return Ok(None);
        };
        let tpath = format!("{ppath}.baseColorTexture");
        let texture = info.texture();
        let source = texture.source();
        let Some(slot) = self.image(&source)? else {
            self.warn(format!(
                "{tpath}: ignored (images[{}] is a JPEG, which this build does not decode; only PNG); \
                 albedo is baseColorFactor alone",
                source.index()
            ));
            return Ok(None);
        };
        let sampler = texture.sampler();
        if info.tex_coord() != 0 {
            self.warn(format!(
                "{tpath}.texCoord: {} not read: the texture is looked up at TEXCOORD_0",
                info.tex_coord()
            ));
        }
        if info.extensions().is_some_and(|e| e.contains_key("KHR_texture_transform")) {
            self.warn(format!(
                "{tpath}.extensions.KHR_texture_transform: ignored; the texture is looked up \
                 at the untransformed coordinates"
            ));
        }
        if sampler.mag_filter() == Some(g::texture::MagFilter::Nearest) {
            self.warn(format!(
                "samplers[{}].magFilter: NEAREST ignored; lookups are bilinear",
                sampler.index().unwrap_or(0)
            ));
        }
        Ok(Some((slot, [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())])))
    }

    /// Warns of what the material holds that the scene's material does not keep: blends between
    /// kinds, an unused ior, alpha, textures other than the base colour, other extensions.
    fn warn_unmapped(&mut self, m: &g::Material, material: &Material, path: &str) {
        let pbr = m.pbr_metallic_roughness();
        let ppath = format!("{path}.pbrMetallicRoughness");
        let [.., alpha] = pbr.base_color_factor();
        let metallic = pbr.metallic_factor();
        let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
        let dielectric = matches!(material, Material::Dielectric { .. });
        let emits = matches!(material, Material::Emissive { .. });
        if !emits && !dielectric && metallic != 0.0 && metallic != 1.0 {
            self.warn(format!(
                "{ppath}.metallicFactor: {metallic} is not blended: ≥ {KIND_THRESHOLD} is metal, below is lambertian"
            ));
        }
        if !emits && transmission != 0.0 && transmission != 1.0 {
            self.warn(format!(
                "{path}.extensions.KHR_materials_transmission.transmissionFactor: {transmission} is not blended: \
                 ≥ {KIND_THRESHOLD} is dielectric"
            ));
        }
        if m.ior().is_some() && !dielectric {
            self.warn(format!(
                "{path}.extensions.KHR_materials_ior: ignored: the material is not transmissive"
            ));
        }
        if alpha < 1.0 || m.alpha_mode() != g::material::AlphaMode::Opaque {
            self.warn(format!(
                "{path}: alpha ignored (baseColorFactor alpha {alpha}, alphaMode {:?}): surfaces are opaque",
                m.alpha_mode()
            ));
        }
        let textures = [
            ("pbrMetallicRoughness.metallicRoughnessTexture", pbr.metallic_roughness_texture().is_some()),
            ("normalTexture", m.normal_texture().is_some()),
            ("occlusionTexture", m.occlusion_texture().is_some()),
            ("emissiveTexture", m.emissive_texture().is_some()),
            (
                "extensions.KHR_materials_transmission.transmissionTexture",
                m.transmission().is_some_and(|t| t.transmission_texture().is_some()),
            ),
        ];
        for (field, present) in textures {
            if present {
                self.warn(format!("{path}.{field}: ignored (only baseColorTexture is mapped)"));
            }
        }
        let others: Vec<String> = m.extensions().map(|e| e.keys().cloned().collect()).unwrap_or_default();
        for e in others {
            self.warn(format!("{path}.extensions.{e}: not mapped, ignored"));
        }
    }

    /// The scene image of glTF image `image`, decoded once however many textures use it; `None`
    /// for a JPEG (this build decodes PNG only). A missing or undecodable image is an error
    /// naming its field.
    fn image(&mut self, image: &g::Image) -> Res<Option<u32>> {
        let index = image.index();
        if let Some(&slot) = self.image_slots.get(&index) {
            return Ok(slot);
        }
        let path = format!("images[{index}]");
        let json = &self.doc.as_json().images[index];
        let (bytes, field) = match (&json.buffer_view, &json.uri) {
            (Some(view), _) => {
                let field = format!("{path}.bufferView");
                let Some(view) = self.doc.views().nth(view.value()) else {
                    return self.err(&field, "names no bufferView of the file");
                };
                let bytes =
                    self.view_bytes(&view).map_err(|r| InputError::new(self.file, &field, r))?.to_vec();
                (bytes, field)
            }
            (None, Some(uri)) => {
                let field = format!("{path}.uri");
                (self.uri_bytes(uri).map_err(|r| InputError::new(self.file, &field, r))?, field)
            }
            (None, None) => return self.err(&path, "has neither a uri nor a bufferView"),
        };
        let slot = if bytes.starts_with(b"\xff\xd8\xff") {
            None
        } else {
            let source = ImageSource::Gltf { file: self.source.to_owned(), image: path.clone() };
            let decoded =
                Image::from_png(&bytes, source).map_err(|r| InputError::new(self.file, &field, r))?;
            self.mapped.push(format!(
                "{path} → image {}×{} (PNG, sRGB decoded to linear)",
                decoded.width, decoded.height
            ));
            self.images.push(decoded);
            Some(self.images.len() as u32 - 1)
        };
        self.image_slots.insert(index, slot);
        Ok(slot)
    }

    fn camera(
        &mut self,
        c: &g::Camera,
        node_path: &str,
        world: Mat4,
        found: &mut Option<CameraSpec>,
    ) -> Res<()> {
        let path = format!("cameras[{}]", c.index());
        if found.is_some() {
            self.warn(format!("{node_path}: {path} not used: the first perspective camera is"));
            return Ok(());
        }
        let g::camera::Projection::Perspective(p) = c.projection() else {
            self.warn(format!(
                "{node_path}: {path} is orthographic, which the book's camera is not; not used"
            ));
            return Ok(());
        };
        let vfov = f64::from(p.yfov()).to_degrees() as f32;
        if !(vfov > 0.0 && vfov < 180.0) {
            return self.err(
                &format!("{path}.perspective.yfov"),
                format!("must be in (0, π) radians, got {}", p.yfov()),
            );
        }
        let lookfrom = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z);
        let vup = world.transform_vector3(Vec3::Y);
        if forward.length_squared() == 0.0 || !forward.is_finite() {
            return self.err(node_path, format!("{path}'s node transform has no view direction"));
        }
        let lookat = lookfrom + forward.normalize();
        let camera = CameraSpec { lookfrom, lookat, vup, vfov, defocus_angle: 0.0, focus_dist: 1.0 };
        if p.aspect_ratio().is_some() {
            self.warn(format!("{path}.perspective.aspectRatio: ignored; the image size sets the aspect"));
        }
        self.mapped.push(format!(
            "{node_path} {path} → camera: lookfrom {}, lookat {}, vup {}, vfov {vfov}, pinhole",
            fmt_vec(lookfrom),
            fmt_vec(lookat),
            fmt_vec(vup)
        ));
        *found = Some(camera);
        Ok(())
    }

    /// One scene mesh per primitive with triangles.
    #[allow(clippy::too_many_arguments)]
    fn mesh(
        &mut self,
        mesh: &g::Mesh,
        node_path: &str,
        world: Mat4,
        source: &Path,
        materials: &mut Vec<NamedMaterial>,
        default_material: u32,
    ) -> Res<Vec<Mesh>> {
        let mut out = Vec::new();
        for prim in mesh.primitives() {
            let path = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
            let mode = prim.mode();
            if matches!(
                mode,
                g::mesh::Mode::Points
                    | g::mesh::Mode::Lines
                    | g::mesh::Mode::LineLoop
                    | g::mesh::Mode::LineStrip
            ) {
                self.warn(format!("{path}.mode: {mode:?} has no surface to render; skipped"));
                continue;
            }
            let (positions, indices) = self.vertices(&prim, &path, world)?;
            let uvs = self.tex_coords(&prim, &path, positions.len(), materials)?;
            let (triangles, triangle_uvs) =
                self.area_triangles(&path, mode, &indices, &positions, uvs.as_deref());
            if triangles.is_empty() {
                self.warn(format!("{path}: no triangles with area; skipped"));
                continue;
            }
            let material = self.primitive_material(&prim, &path, materials, default_material);
            self.warn_ignored_attributes(&prim, &path);
            let label = match mesh.name() {
                Some(n) => format!("{node_path} {path} {n:?}"),
                None => format!("{node_path} {path}"),
            };
            self.mapped.push(format!(
                "{label} → {} triangles, material {:?}",
                triangles.len(),
                materials[material as usize].name
            ));
            out.push(Mesh {
                source: MeshSource::Gltf {
                    file: source.to_owned(),
                    primitive: format!("{node_path} {path}"),
                },
                triangles,
                uvs: uvs.map(|_| triangle_uvs),
                material,
            });
        }
        Ok(out)
    }

    /// A primitive's positions in world space and its indices (one per position where it has
    /// none), checked: every index in range, every position finite.
    fn vertices(&mut self, prim: &g::Primitive, path: &str, world: Mat4) -> Res<(Vec<Vec3>, Vec<u32>)> {
        use g::accessor::{DataType, Dimensions};
        let pos_path = format!("{path}.attributes.POSITION");
        let Some(pos) = prim.get(&g::Semantic::Positions) else {
            return self.err(&pos_path, "missing: a primitive needs vertex positions");
        };
        self.check_accessor(&pos, &pos_path, &[DataType::F32], Dimensions::Vec3, false)?;
        let index_path = format!("{path}.indices");
        if let Some(ind) = prim.indices() {
            self.check_accessor(
                &ind,
                &index_path,
                &[DataType::U8, DataType::U16, DataType::U32],
                Dimensions::Scalar,
                false,
            )?;
        }
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(Vec::as_slice));
        let Some(positions) = reader.read_positions() else {
            return self.err(&pos_path, "cannot be read");
        };
        let positions: Vec<Vec3> = positions.map(|p| world.transform_point3(Vec3::from(p))).collect();
        let indices: Vec<u32> = match reader.read_indices() {
            Some(ind) => ind.into_u32().collect(),
            None if prim.indices().is_some() => return self.err(&index_path, "cannot be read"),
            None => (0..positions.len() as u32).collect(),
        };
        if let Some((k, &i)) = indices.iter().enumerate().find(|(_, &i)| i as usize >= positions.len()) {
            return self.err(
                &index_path,
                format!("index {k} is {i}, but POSITION has {} vertices", positions.len()),
            );
        }
        if positions.iter().any(|p| !p.is_finite()) {
            return self.err(&pos_path, "a vertex is not finite after the node transform");
        }
        Ok((positions, indices))
    }

    /// The primitive's triangles with area, and their texture coordinates where it has them.
    /// Zero-area triangles have no surface to hit (as in OBJ meshes): dropped with a warning.
    fn area_triangles(
        &mut self,
        path: &str,
        mode: g::mesh::Mode,
        indices: &[u32],
        positions: &[Vec3],
        uvs: Option<&[Vec2]>,
    ) -> (Vec<[Vec3; 3]>, Vec<[Vec2; 3]>) {
        let corners = corners(mode, indices.len());
        if mode == g::mesh::Mode::Triangles && !indices.len().is_multiple_of(3) {
            self.warn(format!(
                "{path}: {} indices is not a multiple of 3; the last {} ignored",
                indices.len(),
                indices.len() % 3
            ));
        }
        let mut triangles = Vec::with_capacity(corners.len());
        let mut triangle_uvs = Vec::with_capacity(if uvs.is_some() { corners.len() } else { 0 });
        let mut degenerate = 0;
        for [a, b, c] in corners {
            let [a, b, c] = [indices[a] as usize, indices[b] as usize, indices[c] as usize];
            let t = [positions[a], positions[b], positions[c]];
            if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                triangles.push(t);
                if let Some(uv) = uvs {
                    triangle_uvs.push([uv[a], uv[b], uv[c]]);
                }
            } else {
                degenerate += 1;
            }
        }
        if degenerate > 0 {
            self.warn(format!(
                "{path}: dropped {degenerate} zero-area triangles of {}",
                degenerate + triangles.len()
            ));
        }
        (triangles, triangle_uvs)
    }

    /// The primitive's material, or glTF's default material (added once, at `default_material`).
    fn primitive_material(
        &mut self,
        prim: &g::Primitive,
        path: &str,
        materials: &mut Vec<NamedMaterial>,
        default_material: u32,
    ) -> u32 {
        if let Some(i) = prim.material().index() {
            return i as u32;
        }
        if materials.len() == default_material as usize {
            let material = Material::Metal { albedo: Vec3::ONE.into(), fuzz: 1.0 };
            self.mapped.push(format!("glTF's default material → {}", describe(&material)));
            materials.push(NamedMaterial { name: "gltf-default".into(), material });
        }
        self.warn(format!(
            "{path}.material: none, so glTF's default material (white, metallic 1, roughness 1): \
             a rough white metal"
        ));
        default_material
    }

    fn warn_ignored_attributes(&mut self, prim: &g::Primitive, path: &str) {
        for (field, what) in [("COLOR_0", "vertex colours"), ("NORMAL", "normals")] {
            if prim.attributes().any(|(s, _)| s.to_string() == field) {
                self.warn(format!(
                    "{path}.attributes.{field}: {what} ignored (shading uses the material and the geometric normal)"
                ));
            }
        }
        if prim.morph_targets().len() > 0 {
            self.warn(format!("{path}.targets: morph targets ignored"));
        }
    }

    /// A primitive's `TEXCOORD_0`, one per vertex, where its material has an image albedo (other
    /// primitives need none); `None` with a warning where that material's primitive lacks them.
    fn tex_coords(
        &mut self,
        prim: &g::Primitive,
        path: &str,
        vertices: usize,
        materials: &[NamedMaterial],
    ) -> Res<Option<Vec<Vec2>>> {
        use g::accessor::{DataType, Dimensions};
        let textured = prim.material().index().and_then(|i| materials.get(i)).is_some_and(|m| {
            matches!(
                m.material,
                Material::Lambertian { albedo: Texture::Image { .. } }
                    | Material::Metal { albedo: Texture::Image { .. }, .. }
            )
        });
        if !textured {
            return Ok(None);
        }
        let uv_path = format!("{path}.attributes.TEXCOORD_0");
        let Some(accessor) = prim.get(&g::Semantic::TexCoords(0)) else {
            self.warn(format!(
                "{uv_path}: missing, but the material has a baseColorTexture; each triangle is \
                 textured at (0, 0), (1, 0), (0, 1)"
            ));
            return Ok(None);
        };
        self.check_accessor(
            &accessor,
            &uv_path,
            &[DataType::F32, DataType::U8, DataType::U16],
            Dimensions::Vec2,
            true,
        )?;
        if accessor.count() != vertices {
            return self.err(
                &uv_path,
                format!(
                    "accessors[{}] has {} elements, but POSITION has {vertices} vertices",
                    accessor.index(),
                    accessor.count()
                ),
            );
        }
        let buffers = &self.buffers;
        let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let Some(read) = reader.read_tex_coords(0) else {
            return self.err(&uv_path, "cannot be read");
        };
        let uvs: Vec<Vec2> = read.into_f32().map(Vec2::from).collect();
        if uvs.iter().any(|uv| !uv.is_finite()) {
            return self.err(&uv_path, "a texture coordinate is not finite");
        }
        Ok(Some(uvs))
    }
}

/// The index-list positions of each triangle of a primitive drawn in `mode` (glTF 2.0 §3.7.2.1).
fn corners(mode: g::mesh::Mode, n: usize) -> Vec<[usize; 3]> {
    match mode {
        g::mesh::Mode::Triangles => (0..n / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        g::mesh::Mode::TriangleStrip => {
            (0..n.saturating_sub(2)).map(|i| [i, i + 1 + i % 2, i + 2 - i % 2]).collect()
        }
        g::mesh::Mode::TriangleFan => (1..n.saturating_sub(1)).map(|i| [i, i + 1, 0]).collect(),
        _ => Vec::new(),
    }
}

/// A camera that frames the meshes' bounding sphere, looking down −Z.
fn framing_camera(meshes: &[Mesh]) -> CameraSpec {
    let points = meshes.iter().flat_map(|m| m.triangles.iter().flatten());
    let (lo, hi) = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let center = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() / 2.0).max(1e-3);
    let dist = radius / (DEFAULT_VFOV / 2.0).to_radians().sin();
    CameraSpec {
        lookfrom: center + Vec3::Z * dist,
        lookat: center,
        vup: Vec3::Y,
        vfov: DEFAULT_VFOV,
        defocus_angle: 0.0,
        focus_dist: dist,
    }
}

/// A crate error as ours: validation errors carry the glTF JSON path (`["KEY"]` written as
/// `.KEY`, as our scene files' paths are).
fn crate_error(file: &str, e: g::Error) -> InputError {
    match e {
        g::Error::Validation(errors) => {
            let (path, error) = &errors[0];
            let more = match errors.len() {
                1 => String::new(),
                n => format!(" (and {} more problems)", n - 1),
            };
            InputError::new(file, dotted(&path.to_string()), format!("{error}{more}"))
        }
        g::Error::Deserialize(e) => InputError::new(file, "", format!("not valid glTF JSON: {e}")),
        g::Error::Binary(e) => InputError::new(file, "", format!("not a valid GLB file: {e:?}")),
        e => InputError::new(file, "", format!("cannot read as glTF: {e}")),
    }
}

/// `a["B"]` → `a.B`.
fn dotted(path: &str) -> String {
    path.replace("[\"", ".").replace("\"]", "")
}

/// `%20` and the like decoded, as glTF URIs are percent-encoded.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes.get(i + 1..i + 3).and_then(|h| std::str::from_utf8(h).ok());
        match (bytes[i], hex.and_then(|h| u8::from_str_radix(h, 16).ok())) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn fmt_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// A scene albedo: `factor` alone, or times image `image` (wraps along u and v).
fn albedo(factor: Vec3, image: Option<(u32, [Wrap; 2])>) -> Texture {
    match image {
        Some((image, wrap)) => Texture::Image { image, wrap, tint: factor },
        None => Texture::Solid(factor),
    }
}

fn wrap(mode: g::texture::WrappingMode) -> Wrap {
    match mode {
        g::texture::WrappingMode::Repeat => Wrap::Repeat,
        g::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
        g::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
    }
}

/// A material as `scene info` shows it.
fn describe(m: &Material) -> String {
    let albedo = |t: &super::Texture| match t {
        super::Texture::Solid(c) => fmt_vec(*c),
        super::Texture::Image { image, wrap, tint } => format!(
            "image {image} (scene image; wrap {}/{}) × {}",
            wrap[0].name(),
            wrap[1].name(),
            fmt_vec(*tint)
        ),
        t => t.kind_name().to_owned(),
    };
    match m {
        Material::Lambertian { albedo: a } => format!("lambertian, albedo {}", albedo(a)),
        Material::Metal { albedo: a, fuzz } => format!("metal, albedo {}, fuzz {fuzz}", albedo(a)),
        Material::Dielectric { ior } => format!("dielectric, ior {ior}"),
        Material::Emissive { radiance } => format!("emissive, radiance {}", fmt_vec(*radiance)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_follow_the_spec() {
        assert_eq!(corners(g::mesh::Mode::Triangles, 7), vec![[0, 1, 2], [3, 4, 5]]);
        assert_eq!(corners(g::mesh::Mode::TriangleStrip, 5), vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        assert_eq!(corners(g::mesh::Mode::TriangleFan, 5), vec![[1, 2, 0], [2, 3, 0], [3, 4, 0]]);
        assert!(corners(g::mesh::Mode::TriangleStrip, 2).is_empty());
    }

    #[test]
    fn uris_are_percent_decoded() {
        assert_eq!(percent_decode("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(percent_decode("100%.bin"), "100%.bin");
        assert_eq!(percent_decode("a%zz"), "a%zz");
    }

    #[test]
    fn crate_paths_are_dotted() {
        assert_eq!(
            dotted("meshes[0].primitives[1].attributes[\"POSITION\"]"),
            "meshes[0].primitives[1].attributes.POSITION"
        );
    }
}
