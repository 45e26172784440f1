// Camera rays; twin of src/cpu/camera.rs. Needs `frame` bound.
// The direction is formed from offsets relative to the camera centre, never from world-space
// points on the focus plane: far from the origin those are rounded to the coordinates' ulp,
// which on a plane focus_dist away turns into direction error (pbrt-v4 generates camera rays
// in camera space for the same reason).

fn camera_ray(x: u32, y: u32, u: vec4<f32>) -> Ray {
    let px = f32(x) + (u.x - 0.5);
    let py = f32(y) + (u.y - 0.5);
    let to_target = frame.pixel00_offset + frame.pixel_delta_u * px + frame.pixel_delta_v * py;
    var lens = vec3<f32>(0.0);
    if frame.has_defocus != 0u {
        let d = in_unit_disk(u.z, u.w);
        lens = frame.defocus_disk_u * d.x + frame.defocus_disk_v * d.y;
    }
    return Ray(frame.camera_center + lens, normalize(to_target - lens));
}
