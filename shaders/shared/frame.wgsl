// Per-render constants; twin of FrameUniform in src/layout.rs.

const BACKGROUND_SKY: u32 = 0u;
const BACKGROUND_CONSTANT: u32 = 1u;

struct Frame {
    camera_center: vec3<f32>,
    has_defocus: u32,
    // Centre of pixel (0, 0) relative to camera_center.
    pixel00_offset: vec3<f32>,
    width: u32,
    pixel_delta_u: vec3<f32>,
    height: u32,
    pixel_delta_v: vec3<f32>,
    max_depth: u32,
    defocus_disk_u: vec3<f32>,
    seed: u32,
    defocus_disk_v: vec3<f32>,
    background_kind: u32,
    background_color: vec3<f32>,
    // Emitting primitives in `lights`.
    light_count: u32,
    // Σ mean radiance × area over the lights (power-proportional choice).
    light_power: f32,
    // Hits nearer than this are ignored (--ray-offset tmin=VALUE; 0 with robust).
    t_min: f32,
    // Textures are looked up at (p − texture_origin) · texture_inv_scale: the stress transform
    // undone (--translate, --scale).
    texture_origin: vec3<f32>,
    texture_inv_scale: f32,
}
