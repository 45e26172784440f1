//! A scene flattened for rendering: spheres in BVH order, material records, BVH nodes. Every
//! method (CPU reference, megakernel, wavefront) renders from one `PackedScene`, so they
//! traverse identical data.

use crate::bvh::{Aabb, Bvh};
use crate::camera::CameraFrame;
use crate::layout::{
    background_kind, material_kind, texture_kind, BvhNode, FrameUniform, MaterialRecord, SphereRecord,
};
use crate::scene::{Background, Material, Scene, Texture};
use crate::settings::{Accel, RenderSettings};
use glam::Vec3;

#[derive(Clone, Debug)]
pub struct PackedScene {
    pub spheres: Vec<SphereRecord>,
    /// Material index of each sphere, parallel to `spheres`.
    pub sphere_material: Vec<u32>,
    pub materials: Vec<MaterialRecord>,
    pub nodes: Vec<BvhNode>,
    pub background: Background,
}

impl PackedScene {
    pub fn new(scene: &Scene, accel: Accel) -> Self {
        let boxes: Vec<Aabb> = scene.spheres.iter().map(|s| sphere_box(s.center, s.radius)).collect();
        let bvh = match accel {
            Accel::Bvh => Bvh::build(&boxes),
            Accel::None => Bvh::single_leaf(&boxes),
        };
        let spheres = bvh
            .order
            .iter()
            .map(|&i| {
                let s = &scene.spheres[i as usize];
                SphereRecord { center: s.center.to_array(), radius: s.radius }
            })
            .collect();
        let sphere_material = bvh.order.iter().map(|&i| scene.spheres[i as usize].material).collect();
        let materials = scene.materials.iter().map(|m| material_record(&m.material)).collect();
        PackedScene {
            spheres,
            sphere_material,
            materials,
            nodes: bvh.nodes,
            background: scene.background.clone(),
        }
    }

    /// Material kinds (`layout::material_kind`) that at least one sphere uses, ascending.
    pub fn material_kinds_used(&self) -> Vec<u32> {
        let mut kinds: Vec<u32> =
            self.sphere_material.iter().map(|&m| self.materials[m as usize].kind).collect();
        kinds.sort_unstable();
        kinds.dedup();
        kinds
    }

    /// Spheres in the largest BVH leaf (all of them with `--accel none`).
    pub fn largest_leaf(&self) -> u32 {
        self.nodes.iter().map(|n| n.count).max().unwrap_or(0)
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
            pixel00: f(camera.pixel00),
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
            _pad: 0,
        }
    }
}

/// The sphere's box, padded by a few ulps so that traversal in f64 (`cpu-f64`) of this f32 box
/// never misses a surface point that rounding put just outside it.
fn sphere_box(center: Vec3, radius: f32) -> Aabb {
    let pad = 1e-6 * (center.abs().max_element() + radius);
    Aabb { min: center - (radius + pad), max: center + (radius + pad) }
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
        Texture::Noise { scale, octaves, color } => (texture_kind::NOISE, color, Vec3::ZERO, scale, octaves),
        Texture::Marble { scale, octaves, color } => {
            (texture_kind::MARBLE, color, Vec3::ZERO, scale, octaves)
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
