// Radiance of escaped rays; twin of src/cpu/background.rs. Needs `frame` bound.

fn background(dir: vec3<f32>) -> vec3<f32> {
    if frame.background_kind == BACKGROUND_CONSTANT {
        return frame.background_color;
    }
    let a = 0.5 * (dir.y + 1.0);
    return vec3<f32>(1.0 - a) + vec3<f32>(0.5, 0.7, 1.0) * a;
}
