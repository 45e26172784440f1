//! Records shared bit-for-bit between Rust and WGSL. The CPU reference traverses these same
//! arrays, so it and the GPU read identical scene data. Each struct names its WGSL twin; the
//! tests in `tests/layout.rs` check sizes and offsets against naga's layout of the shaders.

use bytemuck::{Pod, Zeroable};

/// Primitive kinds as stored in [`PrimitiveRecord::kind`] (WGSL: `PRIM_*` in `primitive.wgsl`).
pub mod primitive_kind {
    pub const SPHERE: u32 = 0;
    pub const QUAD: u32 = 1;
    pub const TRIANGLE: u32 = 2;
}

/// WGSL: `Primitive` in `shaders/shared/primitive.wgsl`. One record for every shape, so the BVH
/// leaves index one array and every method keeps one traversal loop:
/// - sphere: `a` centre, `radius`;
/// - quad: corner `a`, edges `b` and `c` (The Next Week's Q, u, v);
/// - triangle: vertex `a`, edges `b = p1 - a` and `c = p2 - a`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PrimitiveRecord {
    pub a: [f32; 3],
    pub kind: u32,
    pub b: [f32; 3],
    pub radius: f32,
    pub c: [f32; 3],
    /// Index into the material records.
    pub material: u32,
}

/// Material kinds as stored in [`MaterialRecord::kind`] (WGSL: `MATERIAL_*` in `shared/kinds.wgsl`).
pub mod material_kind {
    pub const LAMBERTIAN: u32 = 0;
    pub const METAL: u32 = 1;
    pub const DIELECTRIC: u32 = 2;
    pub const EMISSIVE: u32 = 3;
    /// Kinds in this list (`MATERIAL_KIND_COUNT` in WGSL): the wavefront's material queues,
    /// shade passes and histogram columns follow it (`wavefront::path_state::QueueLayout`).
    pub const COUNT: usize = 4;
}

/// Texture kinds as stored in [`MaterialRecord::texture`] (WGSL: `TEXTURE_*` in `texture.wgsl`).
pub mod texture_kind {
    pub const SOLID: u32 = 0;
    pub const CHECKER: u32 = 1;
    pub const NOISE: u32 = 2;
    pub const MARBLE: u32 = 3;
    pub const WOOD: u32 = 4;
    pub const RIDGED: u32 = 5;
    pub const WARP: u32 = 6;
    pub const CELLULAR: u32 = 7;
    pub const CRACKLE: u32 = 8;
    pub const VALUE: u32 = 9;
    /// An image looked up at the surface's texture coordinates (`scene::image`).
    pub const IMAGE: u32 = 10;

    /// The costly procedural patterns (`scene::Pattern`), which loop over octaves.
    pub fn is_procedural(kind: u32) -> bool {
        (NOISE..=VALUE).contains(&kind)
    }
}

/// WGSL: `Material` in `shaders/shared/material.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MaterialRecord {
    /// Albedo (a noise or marble texture's tint, a checker's even squares), or radiance for an
    /// emitter.
    pub color: [f32; 3],
    /// Fuzz for metal, index of refraction for dielectric, unused otherwise.
    pub param: f32,
    pub kind: u32,
    /// [`texture_kind`] of the albedo (lambertian and metal).
    pub texture: u32,
    /// Octaves of a procedural pattern (noise, marble, ...): the shading-cost knob. For an
    /// image: its index in the texel buffer's headers (bits 0..24, [`image_word`]) and the
    /// wrap codes along u (bits 24..26) and v (bits 26..28).
    pub octaves: u32,
    /// Checker square size, or a procedural pattern's frequency.
    pub scale: f32,
    /// A checker's odd squares.
    pub color2: [f32; 3],
    pub _pad: u32,
}

/// The texel buffer of a scene with image textures (WGSL: `texels` in
/// `shaders/shared/scene.wgsl`): one `array<u32>` holding, in order, the sRGB decoding table
/// (256 f32s as bits, `scene::image::srgb_table`), one header of [`image_word::HEADER_WORDS`]
/// words per image (first texel's word, width, height, unused), then every image's texels (r |
/// g << 8 | b << 16, sRGB-encoded, rows top first).
pub mod image_word {
    /// Words of the decoding table, where the headers start.
    pub const HEADERS: u32 = 256;
    pub const HEADER_WORDS: u32 = 4;
    /// Bits of [`super::MaterialRecord::octaves`] that hold the image's index.
    pub const INDEX_MASK: u32 = 0x00ff_ffff;
    pub const WRAP_U_SHIFT: u32 = 24;
    pub const WRAP_V_SHIFT: u32 = 26;
}

/// WGSL: `UvRecord` in `shaders/shared/image_texture.wgsl`: the texture coordinates of a quad or
/// triangle, one per primitive slot (only in scenes with image textures): `uv0` at corner `a`,
/// and the change along edges `b` (`du`) and `c` (`dv`), so the point `a + α·b + β·c` has
/// coordinates `uv0 + α·du + β·dv` for either shape.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct UvRecord {
    pub uv0: [f32; 2],
    pub du: [f32; 2],
    pub dv: [f32; 2],
}

/// WGSL: `BvhNode` in `shaders/shared/bvh.wgsl`. An interior node has `count == 0`, its left
/// child right after it and its right child at `left_or_first`; a leaf holds primitives
/// `left_or_first .. left_or_first + count`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: [f32; 3],
    pub left_or_first: u32,
    pub max: [f32; 3],
    pub count: u32,
}

/// Background kinds as stored in [`FrameUniform::background_kind`].
pub mod background_kind {
    pub const SKY: u32 = 0;
    pub const CONSTANT: u32 = 1;
}

/// WGSL: `Frame` in `shaders/shared/frame.wgsl`: everything constant over a render.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FrameUniform {
    pub camera_center: [f32; 3],
    pub has_defocus: u32,
    /// Centre of pixel (0, 0) relative to `camera_center` (see `shaders/shared/camera.wgsl`).
    pub pixel00_offset: [f32; 3],
    pub width: u32,
    pub pixel_delta_u: [f32; 3],
    pub height: u32,
    pub pixel_delta_v: [f32; 3],
    pub max_depth: u32,
    pub defocus_disk_u: [f32; 3],
    pub seed: u32,
    pub defocus_disk_v: [f32; 3],
    pub background_kind: u32,
    pub background_color: [f32; 3],
    /// Emitting primitives in the scene's light list (0: nothing to sample). Whether to sample
    /// them is the `NEE` pipeline constant (`PackedScene::pipeline_constants`).
    pub light_count: u32,
    /// Σ over the lights of mean radiance × area: the denominator of a light's probability
    /// under power-proportional choice (`light_table.rs`).
    pub light_power: f32,
    /// Hits nearer than this are ignored (`--ray-offset tmin=VALUE`; 0 with `robust`).
    pub t_min: f32,
    pub _pad: [u32; 2],
    /// Textures are looked up at (p − texture_origin) · texture_inv_scale: the inverse of the
    /// stress transform (`--translate`, `--scale`), so they stay on their surfaces.
    pub texture_origin: [f32; 3],
    pub texture_inv_scale: f32,
}

/// WGSL: `LightEntry` in `shaders/shared/light.wgsl`: one column of the alias table of lights
/// (`light_table.rs`), in the order of `PackedScene::lights`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightEntry {
    /// The light's primitive slot.
    pub slot: u32,
    /// The column whose light is taken when this one's is not kept (its alias; `alias` is a
    /// WGSL keyword).
    pub other: u32,
    /// This column keeps its own light when the second uniform is below this.
    pub threshold: f32,
}

/// WGSL: `Dispatch` in `shaders/megakernel.wgsl`: one dispatch's share of the render.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DispatchParams {
    pub pixel_offset: u32,
    pub pixel_count: u32,
    pub sample_start: u32,
    pub sample_count: u32,
}

/// WGSL: `FilmPixel` in `shaders/shared/film.wgsl`: running sums for one pixel, each a
/// double-float (high part + low part: the rounding error of every addition is kept, so a sum
/// has about 48 bits however many samples it holds). The squares are summed scaled by
/// [`FILM_SQ_SCALE`], so they overflow only past samples of about 1.2e24 instead of 1.8e19.
/// Counters are integers: samples dropped for being NaN or infinite, and rays traced (64 bits).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FilmPixel {
    pub sum_hi: [f32; 3],
    pub invalid: u32,
    pub sum_lo: [f32; 3],
    pub rays_lo: u32,
    pub sum_sq_hi: [f32; 3],
    pub rays_hi: u32,
    pub sum_sq_lo: [f32; 3],
    /// Always 0: the accumulate pass hides its compensated sums' intermediate values behind it
    /// (`opaque` in film.wgsl), so that the shader compiler cannot simplify them away.
    pub zero: u32,
}

/// The film sums each sample's square times this (2^-32; `FILM_SQ_SCALE` in film.wgsl): an exact
/// power of two, so nothing is rounded, and squares of samples below about 7e-15 become
/// subnormal while those up to about 1.2e24 stay finite.
pub const FILM_SQ_SCALE: f64 = 1.0 / 4294967296.0;

/// WGSL: `Wave` in `shaders/wavefront/shared/path_state.wgsl`: the wavefront's numbers for a
/// render (its knobs are pipeline constants: `Plan::knob_constants`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WaveUniform {
    /// Pool size: the length of each queue region.
    pub pool: u32,
    /// Regenerating: samples per chunk of the sample ring (0 in waves).
    pub chunk: u32,
    /// Regenerating: chunks in the sample ring (0 in waves).
    pub ring: u32,
    /// Regenerating: a refill runs only when at most this many paths are live
    /// (`--refill-below` × pool; the pool: every iteration).
    pub refill_live: u32,
}

/// WGSL: `Range` in `shaders/accumulate.wgsl`: the samples l in `first .. first + count` of a
/// share, held at l modulo `ring` (the regenerating wavefront's sample ring).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AccumulateRange {
    pub first: u32,
    pub count: u32,
    pub ring: u32,
    pub pad: u32,
}
