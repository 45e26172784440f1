//! The scene on the GPU: bind group 0 of every method (`shaders/shared/scene.wgsl`).

use super::buffers::{storage_entry, storage_init, uniform_entry};
use super::context::GpuContext;
use crate::layout::FrameUniform;
use crate::packed_scene::PackedScene;
use anyhow::Result;
use bytemuck::cast_slice;
use wgpu::util::DeviceExt;

pub struct SceneBuffers {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    /// Bytes of scene data uploaded (for reports).
    pub bytes: u64,
}

impl SceneBuffers {
    pub fn layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
        ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene"),
            entries: &[
                uniform_entry(0, false),
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, true),
                storage_entry(4, true),
            ],
        })
    }

    pub fn new(ctx: &GpuContext, scene: &PackedScene, frame: &FrameUniform) -> Result<Self> {
        let none = wgpu::BufferUsages::empty();
        let frame_buf = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let spheres = storage_init(ctx, "spheres", cast_slice(&scene.spheres), none)?;
        let sphere_material =
            storage_init(ctx, "sphere materials", cast_slice(&scene.sphere_material), none)?;
        let materials = storage_init(ctx, "materials", cast_slice(&scene.materials), none)?;
        let nodes = storage_init(ctx, "BVH nodes", cast_slice(&scene.nodes), none)?;
        let bytes = [&spheres, &sphere_material, &materials, &nodes].iter().map(|b| b.size()).sum();
        let layout = Self::layout(ctx);
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: spheres.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: sphere_material.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: materials.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: nodes.as_entire_binding() },
            ],
        });
        ctx.check()?;
        Ok(Self { layout, bind_group, bytes })
    }
}
