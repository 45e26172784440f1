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
    var acc = film[dispatch.pixel_offset + p];
    for (var s = 0u; s < dispatch.sample_count; s++) {
        let sample = samples[s * dispatch.pixel_count + p];
        let c = sample.rgb;
        acc.sum_sq.w += sample.w; // rays traced, counted valid or not
        if is_non_finite(c) {
            acc.sum.w += 1.0;
        } else {
            acc.sum += vec4<f32>(c, 0.0);
            acc.sum_sq += vec4<f32>(c * c, 0.0);
        }
    }
    film[dispatch.pixel_offset + p] = acc;
}
