//! The scene on the GPU: bind group 0 of every method (`shaders/shared/scene.wgsl`).
//!
//! Every scene buffer is checked against the adapter's limits before any is created
//! ([`check_fits`]), so a scene too big for the device is an error naming the buffer, not a
//! wgpu validation panic or a lost device halfway through the upload.

use super::buffers::{human_bytes, read_back, storage_entry, storage_init, storage_zeroed, uniform_entry};
use super::context::{AdapterSummary, GpuContext};
use super::memory::{MemoryCategory, MemoryLedger};
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
    /// Pipeline constants of the scene's shaders (`PackedScene::pipeline_constants`).
    scene_constants: [(&'static str, f64); 11],
}

impl SceneBuffers {
    pub fn layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
        ctx.bind_group_layout(
            "scene",
            &[
                uniform_entry(0, false),
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, true),
                storage_entry(4, true),
                storage_entry(5, false),
                storage_entry(6, true),
                storage_entry(7, true),
            ],
        )
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
        let primitives = storage_init(ctx, "primitives", &scene.primitives, none)?;
        let materials = storage_init(ctx, "materials", &scene.materials, none)?;
        let nodes = storage_init(ctx, "BVH nodes", &scene.bvh.gpu_words(&scene.nodes), none)?;
        let lights = storage_init(ctx, "lights", &scene.light_table, none)?;
        let uvs = storage_init(ctx, "texture coordinates", &scene.uvs, none)?;
        let texels = storage_init(ctx, "texels", &scene.texels, none)?;
        let bytes = [&primitives, &materials, &nodes, &lights, &uvs, &texels].iter().map(|b| b.size()).sum();
        memory.add(MemoryCategory::Scene, bytes + frame_buf.size());
        let failures = storage_zeroed(
            ctx,
            "failure counters",
            FAILURE_BYTES,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        )?;
        memory.add(MemoryCategory::Counters, FAILURE_BYTES);
        let layout = Self::layout(ctx);
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: primitives.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: materials.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: nodes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: lights.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: failures.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: uvs.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 7, resource: texels.as_entire_binding() },
            ],
        });
        ctx.check()?;
        Ok(Self {
            layout,
            bind_group,
            bytes,
            failures,
            scene_constants: scene.pipeline_constants(settings, specialize),
        })
    }

    /// The failure counters as they stand (waits for the GPU).
    pub fn read_failures(&self, ctx: &GpuContext) -> Result<Failures> {
        Ok(decode_failures(&read_back::<u32>(ctx, &self.failures, FAILURE_BYTES)?))
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
