// Adds one dispatch's samples to the film, each pixel's in sample order: deterministic, no float
// atomics. Shared by the GPU methods; Rust side: src/gpu/accumulate.rs. `samples` holds
// sample_count rows of pixel_count values (row = sample): rgb radiance, w rays traced.

#include "shared/dispatch.wgsl"
#include "shared/film.wgsl"

@group(0) @binding(0) var<storage, read> samples: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> film: array<FilmPixel>;
@group(0) @binding(2) var<uniform> dispatch: Dispatch;

@compute @workgroup_size(64)
fn accumulate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.x;
    if p >= dispatch.pixel_count {
        return;
    }
    let px = film[dispatch.pixel_offset + p];
    var sum = array<vec3<f32>, 2>(px.sum_hi, px.sum_lo);
    var sum_sq = array<vec3<f32>, 2>(px.sum_sq_hi, px.sum_sq_lo);
    var invalid = px.invalid;
    var rays = vec2<u32>(px.rays_lo, px.rays_hi);
    for (var s = 0u; s < dispatch.sample_count; s++) {
        let sample = samples[s * dispatch.pixel_count + p];
        let c = sample.rgb;
        // Rays traced, counted valid or not, in 64 bits.
        let added = rays.x + u32(sample.w);
        rays = vec2<u32>(added, rays.y + select(0u, 1u, added < rays.x));
        if is_non_finite(c) {
            invalid += 1u;
        } else {
            add_compensated(&sum, c, px.zero);
            let scaled = c * FILM_SQ_ROOT_SCALE;
            add_compensated(&sum_sq, scaled * scaled, px.zero);
        }
    }
    film[dispatch.pixel_offset + p] =
        FilmPixel(sum[0], invalid, sum[1], rays.x, sum_sq[0], rays.y, sum_sq[1], px.zero);
}
