//! A scene flattened for rendering: primitives (spheres, quads, triangles) in BVH order, material
//! records, BVH nodes and the list of lights. Every method (CPU reference, megakernel, wavefront)
//! renders from one `PackedScene`, so they traverse identical data, and samples its lights the
//! same way (`light_options`, the alias table `light_table`).

use crate::bvh::collapse::Collapse;
use crate::bvh::{aila_laine, wide, Aabb, Bvh, BvhLayout, BvhRef, SceneBvh};
use crate::camera::CameraFrame;
use crate::layout::{
    background_kind, image_word, material_kind, primitive_kind, texture_kind, BvhNode, FrameUniform,
    LightEntry, MaterialRecord, PrimitiveRecord, UvRecord,
};
use crate::light_options::{LightOptions, LightSampling, LightSelect};
use crate::light_table;
use crate::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
use crate::options::Specialize;
use crate::primitive_area::area;
use crate::real::Real;
use crate::scene::stress::StressTransform;
use crate::scene::{Background, Material, Scene, Texture};
use crate::settings::{Accel, RenderSettings};
use crate::vec3::V3;
use glam::Vec3;

/// Masks with every `layout::primitive_kind`, `material_kind` and `texture_kind` (each list runs
/// from 0 to its last kind): what `--specialize none` compiles in, and the WGSL defaults.
pub const EVERY_PRIMITIVE_KIND: u32 = (1 << (primitive_kind::TRIANGLE + 1)) - 1;
pub const EVERY_MATERIAL_KIND: u32 = (1 << material_kind::COUNT) - 1;
pub const EVERY_TEXTURE_KIND: u32 = (1 << (texture_kind::IMAGE + 1)) - 1;

#[derive(Clone, Debug)]
pub struct PackedScene {
    /// Every shape, in BVH leaf order.
    pub primitives: Vec<PrimitiveRecord>,
    pub materials: Vec<MaterialRecord>,
    /// The binary build's nodes (`--bvh binary`'s; the others are made from them). With
    /// `--bvh wide`, whose leaves store the primitives in another order, only their boxes hold.
    pub nodes: Vec<BvhNode>,
    /// The BVH in the layout the traversals read, and what building it cost.
    pub bvh: SceneBvh,
    /// Slots in `primitives` of the emitters with non-zero radiance, ascending in the binary
    /// build's order (`with_bvh` renames them, keeping that order): what next-event estimation
    /// picks from.
    pub lights: Vec<u32>,
    /// The alias table over `lights` (same order) for power-proportional choice, or the uniform
    /// table where the lights' power does not add up to a positive finite f32 (then the choice
    /// is uniform whatever `light_options` says: see [`PackedScene::light_select`]).
    pub light_table: Vec<LightEntry>,
    /// Σ mean radiance × area over `lights`, rounded to f32 as every method reads it (0 with the
    /// uniform table).
    pub light_power: f32,
    /// How next-event estimation samples the lights (`--light-sampling`, `--light-select`).
    pub light_options: LightOptions,
    /// How rays leave surfaces, meet spheres and split at glass (`--ray-offset`, `--sphere-hit`,
    /// `--fresnel`).
    pub numerics: NumericOptions,
    /// The stress transform the scene was moved by (`--scale`, `--translate`): textures undo it.
    pub stress: StressTransform,
    pub background: Background,
    /// Texture coordinates per primitive slot (as `primitives`), only where some material has
    /// an image texture (empty otherwise, so other scenes upload and read none).
    pub uvs: Vec<UvRecord>,
    /// The images' texels and their decoding table (`layout::image_word`), empty without image
    /// textures.
    pub texels: Vec<u32>,
    /// Each image's source and its texel bytes, for errors naming what does not fit.
    pub image_sources: Vec<(String, u64)>,
}

impl PackedScene {
    pub fn new(scene: &Scene, accel: Accel) -> Self {
        let (records, uv_records) = records(scene);
        let boxes: Vec<Aabb> = records.iter().map(primitive_box).collect();
        let built = std::time::Instant::now();
        let bvh = match accel {
            Accel::Bvh => Bvh::build(&boxes),
            Accel::None => Bvh::single_leaf(&boxes),
        };
        let build_seconds = built.elapsed().as_secs_f64();
        let primitives: Vec<PrimitiveRecord> = bvh.order.iter().map(|&i| records[i as usize]).collect();
        let textured = scene.materials.iter().any(|m| {
            matches!(
                m.material,
                Material::Lambertian { albedo: Texture::Image { .. } }
                    | Material::Metal { albedo: Texture::Image { .. }, .. }
            )
        });
        let uvs =
            if textured { bvh.order.iter().map(|&i| uv_records[i as usize]).collect() } else { Vec::new() };
        let texels = if textured { texel_buffer(&scene.images) } else { Vec::new() };
        let image_sources =
            scene.images.iter().map(|im| (im.source.to_string(), 4 * im.texels.len() as u64)).collect();
        let materials: Vec<MaterialRecord> =
            scene.materials.iter().map(|m| material_record(&m.material)).collect();
        let lights = (0..primitives.len() as u32)
            .filter(|&i| {
                let m = &materials[primitives[i as usize].material as usize];
                m.kind == material_kind::EMISSIVE && m.color.iter().any(|&c| c > 0.0)
            })
            .collect::<Vec<u32>>();
        let (light_table, light_power) = light_distribution(&primitives, &materials, &lights);
        PackedScene {
            primitives,
            materials,
            bvh: SceneBvh { build_seconds, depth: depth(&bvh), ..SceneBvh::default() },
            nodes: bvh.nodes,
            lights,
            light_table,
            light_power,
            light_options: LightOptions::default(),
            numerics: NumericOptions::default(),
            stress: StressTransform::default(),
            background: scene.background.clone(),
            uvs,
            texels,
            image_sources,
        }
    }

    /// The scene with its BVH in `layout` (`--bvh`; the wide one collapsed by `collapse`), made
    /// from the binary build. The wide
    /// layout stores the primitives in its leaves' order: the lights keep their order (each
    /// names its primitive's new slot), so every method samples the same lights with the same
    /// random numbers whatever the layout. Errors where the layout cannot hold the scene.
    pub fn with_bvh(mut self, layout: BvhLayout, collapse: Collapse) -> Result<Self, String> {
        let start = std::time::Instant::now();
        match layout {
            BvhLayout::Binary => {}
            BvhLayout::AilaLaine => {
                self.bvh.aila_laine = aila_laine::from_binary(&self.nodes);
                self.bvh.depth = self.bvh.depth.saturating_sub(1).max(1);
            }
            BvhLayout::Wide => {
                let boxes: Vec<Aabb> = self.primitives.iter().map(primitive_box).collect();
                let built = wide::build(&self.nodes, &boxes, collapse)?;
                self.reorder(&built.order);
                self.bvh.wide = built.nodes;
                self.bvh.depth = built.depth;
            }
        }
        self.bvh.layout = layout;
        self.bvh.build_seconds += start.elapsed().as_secs_f64();
        Ok(self)
    }

    /// The scene with the GPU's traversal stack where `stack` says (`--stack`).
    pub fn with_stack(mut self, stack: crate::bvh::stack::BvhStack) -> Self {
        self.bvh.stack = stack;
        self
    }

    /// Stores the primitive in slot `order[i]` at slot `i`, and renames every slot the scene
    /// holds (lights, the alias table) to match.
    fn reorder(&mut self, order: &[u32]) {
        let mut new_slot = vec![0u32; order.len()];
        for (i, &old) in order.iter().enumerate() {
            new_slot[old as usize] = i as u32;
        }
        self.primitives = order.iter().map(|&o| self.primitives[o as usize]).collect();
        if !self.uvs.is_empty() {
            self.uvs = order.iter().map(|&o| self.uvs[o as usize]).collect();
        }
        for l in &mut self.lights {
            *l = new_slot[*l as usize];
        }
        for e in &mut self.light_table {
            e.slot = new_slot[e.slot as usize];
        }
    }

    /// The nodes the traversals read, in the scene's layout.
    pub fn bvh_nodes(&self) -> BvhRef<'_> {
        self.bvh.nodes(&self.nodes)
    }

    /// The scene with next-event estimation sampling its lights as `options` says.
    pub fn with_light_options(mut self, options: LightOptions) -> Self {
        self.light_options = options;
        self
    }

    /// The scene with rays leaving surfaces, meeting spheres and splitting at glass as
    /// `options` says.
    pub fn with_numerics(mut self, options: NumericOptions) -> Self {
        self.numerics = options;
        self
    }

    /// The scene, already moved by `stress`, with textures looked up where they were before.
    pub fn with_stress(mut self, stress: StressTransform) -> Self {
        self.stress = stress;
        self
    }

    /// `--ray-offset robust`.
    pub fn robust_offsets(&self) -> bool {
        self.numerics.ray_offset == RayOffset::Robust
    }

    /// Where the texture of a surface at `p` is looked up: (p − translate) · (1/scale), with the
    /// origin and inverse scale rounded to `T` as the GPU's frame holds them in f32.
    #[inline(always)]
    pub fn texture_point<T: Real>(&self, p: V3<T>) -> V3<T> {
        let o = V3::of64(glam::DVec3::from(self.stress.translate));
        (p - o) * T::of64(1.0 / self.stress.scale)
    }

    /// The light choice in force: power-proportional only where the scene's lights have a
    /// positive finite total power (otherwise no such choice exists), uniform otherwise.
    pub fn light_select(&self) -> LightSelect {
        match self.light_options.select {
            LightSelect::Power if self.light_power > 0.0 => LightSelect::Power,
            _ => LightSelect::Uniform,
        }
    }

    /// The material of the primitive in `slot`.
    pub fn material_of(&self, slot: u32) -> &MaterialRecord {
        &self.materials[self.primitives[slot as usize].material as usize]
    }

    /// Material kinds (`layout::material_kind`) that at least one primitive uses, ascending.
    pub fn material_kinds_used(&self) -> Vec<u32> {
        let mut kinds: Vec<u32> =
            self.primitives.iter().map(|p| self.materials[p.material as usize].kind).collect();
        kinds.sort_unstable();
        kinds.dedup();
        kinds
    }

    /// The shade passes of `--shade per-texture`: the material kinds of the primitives whose
    /// material has no costly pattern, and the patterns the others have (as indices into
    /// `scene::Pattern::ALL`: texture kind − NOISE), each ascending.
    pub fn shade_classes(&self) -> (Vec<u32>, Vec<u32>) {
        let (mut kinds, mut patterns) = (Vec::new(), Vec::new());
        for p in &self.primitives {
            let m = &self.materials[p.material as usize];
            if texture_kind::is_procedural(m.texture) {
                patterns.push(m.texture - texture_kind::NOISE);
            } else {
                kinds.push(m.kind);
            }
        }
        for v in [&mut kinds, &mut patterns] {
            v.sort_unstable();
            v.dedup();
        }
        (kinds, patterns)
    }

    /// Bit k set when some primitive has `layout::primitive_kind` k: the `PRIM_KINDS` pipeline
    /// constant, so each pipeline compiles only the intersection tests the scene needs.
    pub fn primitive_kinds(&self) -> u32 {
        self.primitives.iter().fold(0, |m, p| m | 1 << p.kind)
    }

    /// Bit k set when some primitive's material has `layout::material_kind` k: the
    /// `MATERIAL_KINDS` pipeline constant.
    pub fn material_kinds(&self) -> u32 {
        self.material_kinds_used().iter().fold(0, |m, k| m | 1 << k)
    }

    /// Bit k set when some primitive's material looks up a texture of `layout::texture_kind` k:
    /// the `TEXTURE_KINDS` pipeline constant. Only lambertian and metal look theirs up; the
    /// other kinds' records carry a solid colour no shader reads as a texture.
    pub fn texture_kinds(&self) -> u32 {
        self.primitives
            .iter()
            .map(|p| &self.materials[p.material as usize])
            .filter(|m| matches!(m.kind, material_kind::LAMBERTIAN | material_kind::METAL))
            .fold(0, |mask, m| mask | 1 << m.texture)
    }

    /// The pipeline constants every pass that binds the scene takes, besides its own: the kinds
    /// compiled in, `PRIM_KINDS`, `MATERIAL_KINDS` and `TEXTURE_KINDS` (the scene's with
    /// `--specialize scene`, every kind with `none`); `NEE` (next-event estimation on, in a scene
    /// with lights), and how NEE samples: `LIGHT_SOLID_ANGLE` (spheres by the cone they subtend)
    /// and `LIGHT_POWER` (choice by power); `RAY_ROBUST`, `SPHERE_BOOK` and `FRESNEL_EXACT`
    /// (`numerics`); `ROULETTE` (`--roulette on`); `BVH_LAYOUT` (`--bvh`). As constants rather than uniforms so that the
    /// compiler drops the code a render does not use.
    pub fn pipeline_constants(
        &self,
        settings: &RenderSettings,
        specialize: Specialize,
    ) -> [(&'static str, f64); 12] {
        let (prims, materials, textures) = match specialize {
            // An empty scene still needs a valid primitive mask; any kind will do.
            Specialize::Scene => (self.primitive_kinds().max(1), self.material_kinds(), self.texture_kinds()),
            Specialize::None => (EVERY_PRIMITIVE_KIND, EVERY_MATERIAL_KIND, EVERY_TEXTURE_KIND),
        };
        let nee = settings.nee && !self.lights.is_empty();
        let solid_angle = self.light_options.sampling == LightSampling::SolidAngle;
        let power = self.light_select() == LightSelect::Power;
        [
            ("PRIM_KINDS", prims as f64),
            ("MATERIAL_KINDS", materials as f64),
            ("TEXTURE_KINDS", textures as f64),
            ("NEE", nee as u32 as f64),
            ("LIGHT_SOLID_ANGLE", solid_angle as u32 as f64),
            ("LIGHT_POWER", power as u32 as f64),
            ("RAY_ROBUST", self.robust_offsets() as u32 as f64),
            ("SPHERE_BOOK", (self.numerics.sphere_hit == SphereHit::Book) as u32 as f64),
            ("FRESNEL_EXACT", (self.numerics.fresnel == Fresnel::Exact) as u32 as f64),
            ("ROULETTE", settings.roulette as u32 as f64),
            ("BVH_LAYOUT", self.bvh.layout.constant() as f64),
            ("BVH_STACK_WORKGROUP", self.bvh.stack.constant() as f64),
        ]
    }

    /// Primitives in the largest BVH leaf (all of them with `--accel none`).
    pub fn largest_leaf(&self) -> u32 {
        self.nodes.iter().map(|n| n.count).max().unwrap_or(0)
    }

    /// Levels of the BVH from the root to its deepest leaf (1: the root is a leaf; 0: empty).
    pub fn bvh_depth(&self) -> u32 {
        if self.nodes.is_empty() {
            return 0;
        }
        // Children of an inner node: the next node and `left_or_first` (shaders/shared/bvh.wgsl).
        let mut deepest = 0;
        let mut stack = vec![(0usize, 1u32)];
        while let Some((i, depth)) = stack.pop() {
            deepest = deepest.max(depth);
            let n = &self.nodes[i];
            if n.count == 0 {
                stack.push((i + 1, depth + 1));
                stack.push((n.left_or_first as usize, depth + 1));
            }
        }
        deepest
    }

    /// The per-render constants, in f32 as every f32 method sees them.
    pub fn frame_uniform(&self, camera: &CameraFrame, settings: &RenderSettings) -> FrameUniform {
        let f = |v: glam::DVec3| v.as_vec3().to_array();
        let (background_kind, background_color) = match self.background {
            Background::Sky => (background_kind::SKY, [0.0; 3]),
            Background::Constant(c) => (background_kind::CONSTANT, c.to_array()),
        };
        FrameUniform {
            camera_center: f(camera.center),
            has_defocus: camera.has_defocus as u32,
            pixel00_offset: f(camera.pixel00 - camera.center),
            width: settings.width,
            pixel_delta_u: f(camera.pixel_delta_u),
            height: settings.height,
            pixel_delta_v: f(camera.pixel_delta_v),
            max_depth: settings.max_depth,
            defocus_disk_u: f(camera.defocus_disk_u),
            seed: settings.seed,
            defocus_disk_v: f(camera.defocus_disk_v),
            background_kind,
            background_color,
            light_count: self.lights.len() as u32,
            light_power: self.light_power,
            t_min: self.numerics.ray_offset.t_min(),
            _pad: [0; 2],
            texture_origin: glam::DVec3::from(self.stress.translate).as_vec3().to_array(),
            texture_inv_scale: (1.0 / self.stress.scale) as f32,
        }
    }
}

/// Levels of the binary build from the root to its deepest leaf.
fn depth(bvh: &Bvh) -> u32 {
    if bvh.nodes.len() <= 1 {
        // One leaf (an empty scene's has no primitive, and count 0 like an inner node).
        bvh.nodes.len() as u32
    } else {
        bvh.depth() as u32
    }
}

/// The alias table over `lights` by emitted power, and the total power as f32; the uniform
/// table and 0 where the total is not a positive finite f32.
fn light_distribution(
    primitives: &[PrimitiveRecord],
    materials: &[MaterialRecord],
    lights: &[u32],
) -> (Vec<LightEntry>, f32) {
    let weights: Vec<f64> = lights
        .iter()
        .map(|&slot| {
            let p = &primitives[slot as usize];
            light_table::power(materials[p.material as usize].color, area::<f64>(p))
        })
        .collect();
    let total = weights.iter().sum::<f64>() as f32;
    match light_table::alias_table(lights, &weights) {
        Some(table) if total > 0.0 && total.is_finite() => (table, total),
        _ => (light_table::uniform_table(lights), 0.0),
    }
}

/// The texel buffer (`layout::image_word`): the decoding table, a header per image, the texels.
fn texel_buffer(images: &[crate::scene::Image]) -> Vec<u32> {
    let mut out: Vec<u32> = crate::scene::image::srgb_table().iter().map(|x| x.to_bits()).collect();
    let mut first = image_word::HEADERS + image_word::HEADER_WORDS * images.len() as u32;
    for im in images {
        out.extend([first, im.width, im.height, 0]);
        first += im.texels.len() as u32;
    }
    for im in images {
        out.extend_from_slice(&im.texels);
    }
    out
}

/// Every shape of the scene as a record, in scene order: spheres, quads, mesh triangles; and
/// each one's texture coordinates (a sphere's unused; a quad's, and a triangle's of a mesh
/// without them, (0, 0) at `a`, (1, 0) at the end of `b`, (0, 1) at the end of `c`).
fn records(scene: &Scene) -> (Vec<PrimitiveRecord>, Vec<UvRecord>) {
    let mut out = Vec::with_capacity(scene.primitive_count());
    let mut uvs = Vec::with_capacity(scene.primitive_count());
    let unit = UvRecord { uv0: [0.0, 0.0], du: [1.0, 0.0], dv: [0.0, 1.0] };
    uvs.extend(std::iter::repeat_n(UvRecord::default(), scene.spheres.len()));
    uvs.extend(std::iter::repeat_n(unit, scene.quads.len()));
    for m in &scene.meshes {
        match &m.uvs {
            Some(corners) => uvs.extend(corners.iter().map(|[a, b, c]| UvRecord {
                uv0: a.to_array(),
                du: (*b - *a).to_array(),
                dv: (*c - *a).to_array(),
            })),
            None => uvs.extend(std::iter::repeat_n(unit, m.triangles.len())),
        }
    }
    for s in &scene.spheres {
        out.push(PrimitiveRecord {
            a: s.center.to_array(),
            kind: primitive_kind::SPHERE,
            radius: s.radius,
            material: s.material,
            ..Default::default()
        });
    }
    let planar = |kind, a: Vec3, b: Vec3, c: Vec3, material| PrimitiveRecord {
        a: a.to_array(),
        kind,
        b: b.to_array(),
        radius: 0.0,
        c: c.to_array(),
        material,
    };
    for q in &scene.quads {
        out.push(planar(primitive_kind::QUAD, q.corner, q.u, q.v, q.material));
    }
    for m in &scene.meshes {
        for t in &m.triangles {
            out.push(planar(primitive_kind::TRIANGLE, t[0], t[1] - t[0], t[2] - t[0], m.material));
        }
    }
    (out, uvs)
}

/// The primitive's box, padded by a few ulps so that traversal in f64 (`cpu-f64`) of this f32
/// box never misses a surface point that rounding put just outside it (and so that a flat
/// quad's box has thickness).
fn primitive_box(p: &PrimitiveRecord) -> Aabb {
    let a = Vec3::from(p.a);
    let b = match p.kind {
        primitive_kind::SPHERE => Aabb { min: a - p.radius, max: a + p.radius },
        _ => {
            let (e1, e2) = (Vec3::from(p.b), Vec3::from(p.c));
            let b = Aabb { min: a, max: a }.grow(a + e1).grow(a + e2);
            // A quad's fourth corner; a triangle's edges already bound it.
            if p.kind == primitive_kind::QUAD {
                b.grow(a + e1 + e2)
            } else {
                b
            }
        }
    };
    let pad = 1e-6 * (b.min.abs().max(b.max.abs()).max_element() + (b.max - b.min).max_element());
    Aabb { min: b.min - pad, max: b.max + pad }
}

fn material_record(m: &Material) -> MaterialRecord {
    let (kind, albedo, param) = match *m {
        Material::Lambertian { albedo } => (material_kind::LAMBERTIAN, albedo, 0.0),
        Material::Metal { albedo, fuzz } => (material_kind::METAL, albedo, fuzz),
        Material::Dielectric { ior } => (material_kind::DIELECTRIC, Texture::Solid(Vec3::ONE), ior),
        Material::Emissive { radiance } => (material_kind::EMISSIVE, Texture::Solid(radiance), 0.0),
    };
    let (texture, color, color2, scale, octaves) = match albedo {
        Texture::Solid(c) => (texture_kind::SOLID, c, Vec3::ZERO, 0.0, 0),
        Texture::Checker { scale, even, odd } => (texture_kind::CHECKER, even, odd, scale, 0),
        Texture::Procedural { pattern, scale, octaves, color } => {
            (pattern.kind(), color, Vec3::ZERO, scale, octaves)
        }
        Texture::Image { image, wrap, tint } => {
            let word = image
                | wrap[0].code() << image_word::WRAP_U_SHIFT
                | wrap[1].code() << image_word::WRAP_V_SHIFT;
            (texture_kind::IMAGE, tint, Vec3::ZERO, 0.0, word)
        }
    };
    MaterialRecord {
        color: color.to_array(),
        param,
        kind,
        texture,
        octaves,
        scale,
        color2: color2.to_array(),
        _pad: 0,
    }
}
