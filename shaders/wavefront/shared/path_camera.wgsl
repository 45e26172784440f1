// The camera ray of a share's sample: generate's, and with `CAMERA_IN_PLACE` (queues on, no
// ray sort) intersect's and shade's, which make it where they use it instead of reading 32 bytes
// of path state that generate would have written for it. The same function of the same pixel and
// sample, so every pass traces and shades the same ray.

fn sample_camera_ray(l: u32) -> Ray {
    let pixel = sample_pixel(l);
    let x = pixel % frame.width;
    let y = pixel / frame.width;
    return camera_ray(x, y, uniform4(pixel, sample_number(l), 0u, PURPOSE_CAMERA, frame.seed));
}
