// Adds samples to the film, each pixel's in sample order: deterministic, no float atomics.
// Shared by the GPU methods; Rust side: src/gpu/accumulate.rs. `accumulate` takes a whole
// dispatch: `samples` holds sample_count rows of pixel_count values (row = sample). The
// regenerating wavefront's `accumulate_range` takes the samples l in [first, first + count) of
// its share (l = sample row × pixel_count + pixel), held at l modulo `ring`. Each value: rgb
// radiance, w rays traced.

#include "shared/dispatch.wgsl"
#include "shared/film.wgsl"

// Twin of AccumulateRange in src/layout.rs.
struct Range {
    first: u32,
    count: u32,
    ring: u32,
    pad: u32,
}

@group(0) @binding(0) var<storage, read> samples: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> film: array<FilmPixel>;
@group(0) @binding(2) var<uniform> dispatch: Dispatch;
// Written on the GPU by the wavefront's schedule_decide (wavefront/queue_setup.wgsl).
@group(0) @binding(3) var<storage, read> range: Range;

// Adds one sample to a pixel's sums (the film's arithmetic, one place for both entry points).
fn add_sample(sum: ptr<function, array<vec3<f32>, 2>>, sum_sq: ptr<function, array<vec3<f32>, 2>>,
              invalid: ptr<function, u32>, rays: ptr<function, vec2<u32>>, sample: vec4<f32>, zero: u32) {
    let c = sample.rgb;
    // Rays traced, counted valid or not, in 64 bits.
    let added = (*rays).x + u32(sample.w);
    *rays = vec2<u32>(added, (*rays).y + select(0u, 1u, added < (*rays).x));
    if is_non_finite(c) {
        *invalid += 1u;
    } else {
        add_compensated(sum, c, zero);
        let scaled = c * FILM_SQ_ROOT_SCALE;
        add_compensated(sum_sq, scaled * scaled, zero);
    }
}

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
        add_sample(&sum, &sum_sq, &invalid, &rays, samples[s * dispatch.pixel_count + p], px.zero);
    }
    film[dispatch.pixel_offset + p] =
        FilmPixel(sum[0], invalid, sum[1], rays.x, sum_sq[0], rays.y, sum_sq[1], px.zero);
}

// Thread t takes the pixel of sample first + t and that pixel's later samples in the range, so
// each pixel the range touches has one thread, adding in sample order.
@compute @workgroup_size(64)
fn accumulate_range(@builtin(global_invocation_id) gid: vec3<u32>) {
    let pc = dispatch.pixel_count;
    let t = gid.x;
    if t >= min(pc, range.count) {
        return;
    }
    let p = (range.first + t) % pc;
    let px = film[dispatch.pixel_offset + p];
    var sum = array<vec3<f32>, 2>(px.sum_hi, px.sum_lo);
    var sum_sq = array<vec3<f32>, 2>(px.sum_sq_hi, px.sum_sq_lo);
    var invalid = px.invalid;
    var rays = vec2<u32>(px.rays_lo, px.rays_hi);
    let end = range.first + range.count;
    for (var l = range.first + t; l < end; l += pc) {
        add_sample(&sum, &sum_sq, &invalid, &rays, samples[l % range.ring], px.zero);
    }
    film[dispatch.pixel_offset + p] =
        FilmPixel(sum[0], invalid, sum[1], rays.x, sum_sq[0], rays.y, sum_sq[1], px.zero);
}
