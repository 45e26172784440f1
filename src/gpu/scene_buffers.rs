//! The scene on the GPU: bind group 0 of every method (`shaders/shared/scene.wgsl`).
//!
//! Every scene buffer is checked against the adapter's limits before any is created
//! ([`check_fits`]), so a scene too big for the device is an error naming the buffer, not a
//! wgpu validation panic or a lost device halfway through the upload. The primitives and the
//! BVH nodes are split over several bindings where one is too small for them (`scene_split.rs`).

use super::buffers::{human_bytes, read_back, storage_entry, storage_init, storage_zeroed, uniform_entry};
use super::context::{AdapterSummary, GpuContext};
use super::memory::{MemoryCategory, MemoryLedger};
use super::scene_split::{Split, MAX_BINDINGS};
use crate::bvh::BvhLayout;
use crate::layout::FrameUniform;
use crate::numerics::Failures;
use crate::options::Specialize;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use wgpu::util::DeviceExt;

pub struct SceneBuffers {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    /// Bytes of scene data uploaded (for reports).
    pub bytes: u64,
    /// The failure counters the shaders add to (`shared/offset.wgsl`): self-hits, shadow
    /// self-hits, depth-cut paths, each a u64 as two u32 words, low first.
    pub failures: wgpu::Buffer,
    /// Pipeline constants of the scene's shaders (`PackedScene::pipeline_constants`, then how
    /// the primitives and nodes are split over bindings).
    scene_constants: Vec<(&'static str, f64)>,
}

/// Bytes of one primitive record and of one unit of the node binding (`array<vec4<u32>>`).
const PRIMITIVE_BYTES: u64 = std::mem::size_of::<crate::layout::PrimitiveRecord>() as u64;
const NODE_UNIT_BYTES: u64 = 16;
/// The bindings of `primitives_1`… and `nodes_1`… in `shaders/shared/scene.wgsl`.
const FIRST_PRIMITIVE_BINDING: u32 = 8;
const FIRST_NODE_BINDING: u32 = FIRST_PRIMITIVE_BINDING + MAX_BINDINGS as u32 - 1;

impl SceneBuffers {
    pub fn layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
        let mut entries = vec![uniform_entry(0, false)];
        entries.extend((1..FIRST_NODE_BINDING + MAX_BINDINGS as u32 - 1).map(|b| storage_entry(b, b != 5)));
        ctx.bind_group_layout("scene", &entries)
    }

    /// A pass's own pipeline constants plus the scene's, for every pass that binds the scene.
    pub fn constants(&self, own: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
        own.iter().chain(&self.scene_constants).copied().collect()
    }

    pub fn new(
        ctx: &GpuContext,
        scene: &PackedScene,
        frame: &FrameUniform,
        settings: &RenderSettings,
        specialize: Specialize,
        memory: &mut MemoryLedger,
    ) -> Result<Self> {
        check_fits(scene, &ctx.summary)?;
        let none = wgpu::BufferUsages::empty();
        let frame_buf = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Empty arrays (no objects, no lights) bind one zeroed, unused element: the shaders
        // read only the slots the BVH and the light count name.
        let limit = binding_limit(&ctx.summary);
        let words = scene.bvh.gpu_words(&scene.nodes);
        let Some((prim_split, node_split)) = splits(scene.primitives.len() as u64, words.len() as u64, limit)
        else {
            bail!(
                "the scene's primitives or BVH nodes do not fit {MAX_BINDINGS} storage bindings on {}",
                ctx.summary.name
            );
        };
        let primitives = split_buffers(ctx, "primitives", &scene.primitives, &prim_split)?;
        let nodes = split_buffers(ctx, "BVH nodes", &words, &node_split)?;
        drop(words);
        let materials = storage_init(ctx, "materials", &scene.materials, none)?;
        let lights = storage_init(ctx, "lights", &scene.light_table, none)?;
        let uvs = storage_init(ctx, "texture coordinates", &scene.uvs, none)?;
        let texels = storage_init(ctx, "texels", &scene.texels, none)?;
        let bytes = primitives
            .iter()
            .chain(&nodes)
            .chain([&materials, &lights, &uvs, &texels])
            .map(|b| b.size())
            .sum();
        memory.add(MemoryCategory::Scene, bytes + frame_buf.size());
        let failures = storage_zeroed(
            ctx,
            "failure counters",
            FAILURE_BYTES,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        )?;
        memory.add(MemoryCategory::Counters, FAILURE_BYTES);
        let layout = Self::layout(ctx);
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: primitives[0].as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: materials.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: nodes[0].as_entire_binding() },
            wgpu::BindGroupEntry { binding: 4, resource: lights.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 5, resource: failures.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 6, resource: uvs.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 7, resource: texels.as_entire_binding() },
        ];
        // The further bindings; those past the array's last repeat its first buffer, unread.
        for (first, buffers) in [(FIRST_PRIMITIVE_BINDING, &primitives), (FIRST_NODE_BINDING, &nodes)] {
            for b in 1..MAX_BINDINGS as usize {
                let buffer = buffers.get(b).unwrap_or(&buffers[0]);
                entries.push(wgpu::BindGroupEntry {
                    binding: first + b as u32 - 1,
                    resource: buffer.as_entire_binding(),
                });
            }
        }
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &layout,
            entries: &entries,
        });
        ctx.check()?;
        let mut scene_constants = scene.pipeline_constants(settings, specialize).to_vec();
        scene_constants.extend(prim_split.constants(["PRIM_BINDINGS", "PRIM_PER_BINDING"]));
        scene_constants.extend(node_split.constants(["NODE_BINDINGS", "NODE_PER_BINDING"]));
        Ok(Self { layout, bind_group, bytes, failures, scene_constants })
    }

    /// The failure counters as they stand (waits for the GPU).
    pub fn read_failures(&self, ctx: &GpuContext) -> Result<Failures> {
        Ok(decode_failures(&read_back::<u32>(ctx, &self.failures, FAILURE_BYTES)?))
    }
}

/// One storage buffer per binding of `split` over `data` (at least one: an empty array binds
/// one zeroed element).
fn split_buffers<T: bytemuck::Pod>(
    ctx: &GpuContext,
    label: &'static str,
    data: &[T],
    split: &Split,
) -> Result<Vec<wgpu::Buffer>> {
    (0..split.bindings)
        .map(|b| storage_init(ctx, label, &data[split.range(b)], wgpu::BufferUsages::empty()))
        .collect()
}

/// The bytes one storage binding may hold on `adapter`: a binding is bounded by both limits,
/// which wgpu checks separately.
fn binding_limit(adapter: &AdapterSummary) -> u64 {
    adapter.max_storage_buffer_binding_size.min(adapter.max_buffer_size)
}

/// How `primitives` records and `node_units` 16-byte units of BVH nodes split under `limit`
/// bytes a binding; None for an array that eight bindings cannot hold.
fn splits(primitives: u64, node_units: u64, limit: u64) -> Option<(Split, Split)> {
    Some((Split::new(primitives, PRIMITIVE_BYTES, limit)?, Split::new(node_units, NODE_UNIT_BYTES, limit)?))
}

/// Bytes of one element of the arrays split over several bindings (by their label in
/// [`buffer_sizes`]); None for the arrays bound whole.
fn split_element(label: &str) -> Option<u64> {
    match label {
        "primitives" => Some(PRIMITIVE_BYTES),
        "BVH nodes" => Some(NODE_UNIT_BYTES),
        _ => None,
    }
}

/// The smallest per-binding limit under which the buffer `label` of `size` bytes
/// ([`buffer_sizes`]) can be bound: its size, or for the split arrays the share of the
/// [`MAX_BINDINGS`] bindings that takes the most whole elements.
pub fn binding_needed(label: &str, size: u64) -> u64 {
    match split_element(label) {
        Some(element) => (size / element).div_ceil(MAX_BINDINGS) * element,
        None => size,
    }
}

/// Bytes of the failure counters: three u64s.
pub const FAILURE_BYTES: u64 = 24;

/// The failure counters from their words (`shared/offset.wgsl`: low word first).
pub fn decode_failures(words: &[u32]) -> Failures {
    let word = |i: usize| (words[2 * i + 1] as u64) << 32 | words[2 * i] as u64;
    Failures { self_hits: word(0), shadow_self_hits: word(1), depth_cut: word(2) }
}

/// The storage buffers a scene needs: (label, bytes), labelled as in errors and in wgpu.
pub fn buffer_sizes(scene: &PackedScene) -> [(&'static str, u64); 6] {
    use std::mem::size_of_val;
    [
        ("primitives", size_of_val(scene.primitives.as_slice()) as u64),
        ("materials", size_of_val(scene.materials.as_slice()) as u64),
        (
            "BVH nodes",
            scene.bvh.bytes(&scene.nodes) + if scene.bvh.layout == BvhLayout::Binary { 0 } else { 32 },
        ),
        ("lights", size_of_val(scene.light_table.as_slice()) as u64),
        ("texture coordinates", size_of_val(scene.uvs.as_slice()) as u64),
        ("texels", size_of_val(scene.texels.as_slice()) as u64),
    ]
}

/// Errors out, naming the first scene buffer that is too big, its size, the limit and the
/// adapter, when `scene` cannot be bound on `adapter`.
pub fn check_fits(scene: &PackedScene, adapter: &AdapterSummary) -> Result<()> {
    check_fits_limits(scene, &adapter.name, adapter.max_storage_buffer_binding_size, adapter.max_buffer_size)
}

/// [`check_fits`] against explicit limits: pure, so tests can pose as a smaller adapter.
pub fn check_fits_limits(
    scene: &PackedScene,
    adapter: &str,
    max_storage_buffer_binding_size: u64,
    max_buffer_size: u64,
) -> Result<()> {
    // A storage binding is bounded by both limits; wgpu checks each separately.
    let limit = max_storage_buffer_binding_size.min(max_buffer_size);
    for (label, size) in buffer_sizes(scene) {
        if let Some(element) = split_element(label) {
            let capacity = Split::capacity(element, limit);
            if size > capacity {
                bail!(
                    "the scene ({} primitives) does not fit on {adapter}: its {label} buffer needs {} \
                     ({size} bytes) but the adapter's storage bindings hold at most {} ({limit} bytes) \
                     each (max_storage_buffer_binding_size {max_storage_buffer_binding_size}, \
                     max_buffer_size {max_buffer_size}) and the shaders split it over at most \
                     {MAX_BINDINGS}, {} ({capacity} bytes) in all; use a scene with fewer primitives \
                     or a GPU with larger limits",
                    scene.primitives.len(),
                    human_bytes(size),
                    human_bytes(limit),
                    human_bytes(capacity),
                );
            }
            continue;
        }
        if label == "texels" && size > limit {
            // The images are what the user can act on: name them, largest first.
            let mut images = scene.image_sources.clone();
            images.sort_by_key(|(_, bytes)| std::cmp::Reverse(*bytes));
            let named: Vec<String> = images
                .iter()
                .take(4)
                .map(|(source, bytes)| format!("{source} ({})", human_bytes(*bytes)))
                .collect();
            let more = images.len().saturating_sub(4);
            bail!(
                "the scene's image textures do not fit on {adapter}: their texels need {} ({size} bytes) \
                 but the adapter allows at most {} ({limit} bytes) per storage buffer \
                 (max_storage_buffer_binding_size {max_storage_buffer_binding_size}, max_buffer_size \
                 {max_buffer_size}); the images, 4 bytes a texel: {}{}; use smaller images",
                human_bytes(size),
                human_bytes(limit),
                named.join(", "),
                if more > 0 { format!(" and {more} more") } else { String::new() },
            );
        }
        if size > limit {
            bail!(
                "the scene ({} primitives) does not fit on {adapter}: its {label} buffer needs {} \
                 ({size} bytes) but the adapter allows at most {} ({limit} bytes) per storage \
                 buffer (max_storage_buffer_binding_size {max_storage_buffer_binding_size}, \
                 max_buffer_size {max_buffer_size}); use a scene with fewer primitives or a GPU with \
                 larger limits",
                scene.primitives.len(),
                human_bytes(size),
                human_bytes(limit),
            );
        }
    }
    Ok(())
}
