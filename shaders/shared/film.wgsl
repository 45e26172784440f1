// Per-pixel running sums; twin of FilmPixel in src/layout.rs and src/film.rs. Each sum is a
// double-float: hi + lo, lo holding the rounding error of every addition (Knuth's TwoSum), so a
// pixel keeps about 48 bits however many samples it sums, where a plain f32 sum adds each new
// sample to an ever larger number and loses its low bits.

struct FilmPixel {
    // Σ of the finite samples (hi); the count of NaN/Inf samples dropped.
    sum_hi: vec3<f32>,
    invalid: u32,
    // Σ of the finite samples (lo); rays traced by the pixel's paths (low 32 bits).
    sum_lo: vec3<f32>,
    rays_lo: u32,
    // Σ (sample · FILM_SQ_ROOT_SCALE)² (hi); rays traced (high 32 bits).
    sum_sq_hi: vec3<f32>,
    rays_hi: u32,
    // Σ (sample · FILM_SQ_ROOT_SCALE)² (lo).
    sum_sq_lo: vec3<f32>,
    // Always 0, and read from memory so that no compiler can know it: see `opaque`.
    zero: u32,
}

// Squares are summed scaled by 2^-32 (FILM_SQ_SCALE in src/layout.rs): exact, and finite up to
// samples of about 1.2e24 instead of 1.8e19. Each sample is scaled before it is squared.
const FILM_SQ_ROOT_SCALE: f32 = 1.52587890625e-5; // 2^-16

// NaN or infinite in any channel, tested on the bits: comparisons like x != x may be folded away
// by an optimising shader compiler.
fn is_non_finite(c: vec3<f32>) -> bool {
    let exp = bitcast<vec3<u32>>(c) & vec3<u32>(0x7f800000u);
    return any(exp == vec3<u32>(0x7f800000u));
}

// x, hidden from the optimiser: its bits or'ed with `zero`, which is 0 but read from the film.
// Compensated sums compute rounding errors as (a + b) - a - b, which is 0 in exact arithmetic,
// and shader compilers may simplify it so (Mesa's NIR does, for operations SPIR-V does not mark
// NoContraction, which WGSL cannot ask for): the sums were plain f32 sums on llvmpipe until the
// intermediate values were hidden.
fn opaque(x: vec3<f32>, zero: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(bitcast<vec3<u32>>(x) | vec3<u32>(zero));
}

// Adds x to the double-float (hi, lo): TwoSum finds the rounding error of hi + x exactly (six
// additions, no branch, whatever the magnitudes), lo takes it, and FastTwoSum moves what lo has
// gathered back into hi, so lo stays below half an ulp of hi and its own rounding is ~2^-48 of
// the sum (Dekker 1971; the QD library's double-double addition). `zero` hides the intermediate
// sums from the optimiser (`opaque`).
fn add_compensated(sum: ptr<function, array<vec3<f32>, 2>>, x: vec3<f32>, zero: u32) {
    let hi = (*sum)[0];
    let s = opaque(hi + x, zero);
    let b = opaque(s - hi, zero);
    let err = (hi - (s - b)) + (x - b);
    let t = (*sum)[1] + err;
    let h = opaque(s + t, zero);
    (*sum)[0] = h;
    (*sum)[1] = t - (h - s);
}
