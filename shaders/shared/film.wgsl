// Per-pixel running sums; twin of FilmPixel in src/layout.rs and src/film.rs.

struct FilmPixel {
    // rgb: sum of finite samples; w: count of dropped NaN/Inf samples.
    sum: vec4<f32>,
    // rgb: sum of squares of finite samples; w: rays traced by the pixel's paths.
    sum_sq: vec4<f32>,
}

// NaN or infinite in any channel, tested on the bits: comparisons like x != x may be folded away
// by an optimising shader compiler.
fn is_non_finite(c: vec3<f32>) -> bool {
    let exp = bitcast<vec3<u32>>(c) & vec3<u32>(0x7f800000u);
    return any(exp == vec3<u32>(0x7f800000u));
}
