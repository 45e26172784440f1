// Camera rays; twin of src/cpu/camera.rs. Needs `frame` bound.

fn camera_ray(x: u32, y: u32, u: vec4<f32>) -> Ray {
    let px = f32(x) + (u.x - 0.5);
    let py = f32(y) + (u.y - 0.5);
    let target_point = frame.pixel00 + frame.pixel_delta_u * px + frame.pixel_delta_v * py;
    var origin = frame.camera_center;
    if frame.has_defocus != 0u {
        let d = in_unit_disk(u.z, u.w);
        origin = frame.camera_center + frame.defocus_disk_u * d.x + frame.defocus_disk_v * d.y;
    }
    return Ray(origin, normalize(target_point - origin));
}
