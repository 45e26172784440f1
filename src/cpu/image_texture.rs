//! Image textures: a surface point's texture coordinates and the bilinear lookup at them; twin of
//! `shaders/shared/image_texture.wgsl`. The texel buffer's layout is `layout::image_word`.
//!
//! The lookup is bilinear in linear space: u maps across the width with texel centres at
//! (i + ½) / width (v likewise down the rows, v = 0 the top row, as glTF defines UVs), the four
//! texels around the point are decoded through the buffer's sRGB table, each index wrapped by
//! its axis's mode, and blended by the point's fractional position.

use super::{real::Real, vec3::V3};
use crate::layout::{image_word, primitive_kind, MaterialRecord, PrimitiveRecord, UvRecord};

/// How far from the image a coordinate is followed, in texels: beyond, f32 has no fraction left
/// (2^24), and the integer wrap arithmetic stays inside i32 on the GPU.
pub const TEXEL_RANGE: f32 = 16_777_216.0;

/// Wrap codes (`scene::Wrap::code`).
pub const WRAP_REPEAT: u32 = 0;
pub const WRAP_CLAMP: u32 = 1;
pub const WRAP_MIRROR: u32 = 2;

/// Texel index `i` of an axis `n` texels long, wrapped by `mode`.
#[inline(always)]
pub fn wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    match mode {
        WRAP_CLAMP => i.clamp(0, n - 1),
        WRAP_MIRROR => {
            let m = i.rem_euclid(2 * n);
            if m >= n {
                2 * n - 1 - m
            } else {
                m
            }
        }
        _ => i.rem_euclid(n),
    }
}

/// The texture coordinates at `p` on primitive `prim` (slot `slot`): a quad's or triangle's from
/// its `UvRecord` at the point's edge coordinates (α, β), a sphere's The Next Week's
/// (φ / 2π, θ / π) of its outward normal with v flipped so that v = 0 is the top (+y).
#[inline(always)]
pub fn surface_uv<T: Real>(prim: &PrimitiveRecord, uv: &UvRecord, p: V3<T>) -> [T; 2] {
    let (one, two) = (T::one(), T::of(2.0));
    let a = V3::<T>::of(prim.a);
    if prim.kind == primitive_kind::SPHERE {
        let n = (p - a) / T::of(prim.radius);
        let phi = (-n.z).atan2(n.x) + T::PI();
        let theta = (-n.y).max(-one).min(one).acos();
        return [phi / (two * T::PI()), one - theta / T::PI()];
    }
    let (b, c) = (V3::<T>::of(prim.b), V3::<T>::of(prim.c));
    let n = b.cross(c);
    let w = n / n.dot(n);
    let h = p - a;
    let (alpha, beta) = (w.dot(h.cross(c)), w.dot(b.cross(h)));
    let f = |i: usize| T::of(uv.uv0[i]) + T::of(uv.du[i]) * alpha + T::of(uv.dv[i]) * beta;
    [f(0), f(1)]
}

/// The linear colour of texel word `word` through the buffer's decoding table.
#[inline(always)]
fn decode<T: Real>(texels: &[u32], word: u32) -> V3<T> {
    let c = |shift: u32| T::of(f32::from_bits(texels[(word >> shift & 0xff) as usize]));
    V3::new(c(0), c(8), c(16))
}

/// The albedo of image material `m` at texture coordinates `uv`: the bilinear lookup times the
/// tint (`m.color`).
#[inline(always)]
pub fn image_albedo<T: Real>(m: &MaterialRecord, texels: &[u32], uv: [T; 2]) -> V3<T> {
    let header =
        (image_word::HEADERS + image_word::HEADER_WORDS * (m.octaves & image_word::INDEX_MASK)) as usize;
    let (first, width, height) = (texels[header], texels[header + 1], texels[header + 2]);
    let wrap_u = m.octaves >> image_word::WRAP_U_SHIFT & 3;
    let wrap_v = m.octaves >> image_word::WRAP_V_SHIFT & 3;
    let range = T::of(TEXEL_RANGE);
    let half = T::of(0.5);
    // NaN compares false both ways: max/min return the number, so it lands at an edge.
    let x = (uv[0] * T::of(width as f32) - half).max(-range).min(range);
    let y = (uv[1] * T::of(height as f32) - half).max(-range).min(range);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (ix, iy) = (x0.to_f64() as i32, y0.to_f64() as i32);
    let (w, h) = (width as i32, height as i32);
    let (xa, xb) = (wrap_index(ix, w, wrap_u), wrap_index(ix + 1, w, wrap_u));
    let (ya, yb) = (wrap_index(iy, h, wrap_v), wrap_index(iy + 1, h, wrap_v));
    let texel = |x: i32, y: i32| decode::<T>(texels, texels[first as usize + (y * w + x) as usize]);
    let one = T::one();
    let top = texel(xa, ya) * (one - fx) + texel(xb, ya) * fx;
    let bottom = texel(xa, yb) * (one - fx) + texel(xb, yb) * fx;
    (top * (one - fy) + bottom * fy).mul_elem(V3::of(m.color))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::texture_kind;

    #[test]
    fn wrap_modes_follow_gl() {
        let n = 4;
        let all = |mode| (-5..9).map(|i| wrap_index(i, n, mode)).collect::<Vec<_>>();
        assert_eq!(all(WRAP_REPEAT), [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0]);
        assert_eq!(all(WRAP_CLAMP), [0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3]);
        // Period 2n: 0 1 2 3 3 2 1 0, then again.
        assert_eq!(all(WRAP_MIRROR), [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0]);
    }

    /// A 2×2 image, red channel 0, 1 (top row) and 0.2, 1 (bottom), through a linear table of our
    /// own (byte b ↦ b / 255) so that expected values are easy to state.
    fn two_by_two(wrap_u: u32, wrap_v: u32) -> (MaterialRecord, Vec<u32>) {
        let mut texels: Vec<u32> = (0..256).map(|b| (b as f32 / 255.0).to_bits()).collect();
        texels.extend([image_word::HEADERS + 4, 2, 2, 0]);
        texels.extend([0u32, 255, 51, 255]);
        let m = MaterialRecord {
            color: [1.0, 1.0, 1.0],
            texture: texture_kind::IMAGE,
            octaves: wrap_u << image_word::WRAP_U_SHIFT | wrap_v << image_word::WRAP_V_SHIFT,
            ..Default::default()
        };
        (m, texels)
    }

    #[test]
    fn bilinear_weights_and_texel_centres() {
        let (m, tx) = two_by_two(WRAP_CLAMP, WRAP_CLAMP);
        let r = |u: f64, v: f64| image_albedo(&m, &tx, [u, v]).x;
        // Texel centres give the texels exactly.
        assert_eq!(r(0.25, 0.25), 0.0);
        assert_eq!(r(0.75, 0.25), 1.0);
        assert!((r(0.25, 0.75) - 0.2).abs() < 1e-7);
        // Halfway between the centres: the mean of the four.
        assert!((r(0.5, 0.5) - (0.0 + 1.0 + 0.2 + 1.0) / 4.0).abs() < 1e-7);
        // A quarter of a texel right of the top-left centre: 3/4 of it, 1/4 of its neighbour.
        assert!((r(0.25 + 0.125, 0.25) - 0.25).abs() < 1e-7, "{}", r(0.375, 0.25));
        // Clamped: beyond the edge, the edge texels.
        assert_eq!(r(-3.0, 0.25), 0.0);
        assert_eq!(r(7.0, -2.0), 1.0);
        // The tint multiplies.
        let tinted = MaterialRecord { color: [0.5, 0.5, 0.5], ..m };
        assert_eq!(image_albedo(&tinted, &tx, [0.75f64, 0.25]).x, 0.5);
    }

    #[test]
    fn repeat_and_mirror_blend_across_the_edge() {
        // At u = 0 the point is halfway between texel −1 and texel 0.
        let (m, tx) = two_by_two(WRAP_REPEAT, WRAP_CLAMP);
        let r = image_albedo(&m, &tx, [0.0f64, 0.25]).x;
        assert!((r - 0.5).abs() < 1e-7, "repeat: texel −1 is texel 1: {r}");
        assert_eq!(image_albedo(&m, &tx, [1.25f64, 0.25]).x, 0.0, "one period on");
        let (m, tx) = two_by_two(WRAP_MIRROR, WRAP_CLAMP);
        assert_eq!(image_albedo(&m, &tx, [0.0f64, 0.25]).x, 0.0, "mirror: texel −1 is texel 0");
        assert_eq!(image_albedo(&m, &tx, [1.25f64, 0.25]).x, 1.0, "mirrored copy: texel 2 is texel 1");
        // Far out and non-finite coordinates stay in the image.
        for u in [1e30, -1e30, f64::NAN, f64::INFINITY] {
            let c = image_albedo(&m, &tx, [u, u]).x;
            assert!((0.0..=1.0).contains(&c), "{u}: {c}");
        }
    }

    #[test]
    fn f32_and_f64_agree() {
        let (m, tx) = two_by_two(WRAP_MIRROR, WRAP_REPEAT);
        for (u, v) in [(0.3, 0.9), (-1.7, 2.2), (0.51, 0.49)] {
            let a = image_albedo(&m, &tx, [u as f32, v as f32]).x as f64;
            let b = image_albedo(&m, &tx, [u, v]).x;
            assert!((a - b).abs() < 1e-6, "({u}, {v}): {a} vs {b}");
        }
    }

    #[test]
    fn triangle_and_quad_coordinates_follow_the_edges() {
        let tri = PrimitiveRecord {
            a: [1.0, 0.0, 0.0],
            kind: primitive_kind::TRIANGLE,
            b: [2.0, 0.0, 0.0],
            c: [0.0, 4.0, 0.0],
            ..Default::default()
        };
        let uv = UvRecord { uv0: [0.5, 0.5], du: [0.5, 0.0], dv: [0.0, -0.5] };
        // α = 0.5, β = 0.25.
        let got = surface_uv(&tri, &uv, V3::<f64>::new(2.0, 1.0, 0.0));
        assert_eq!(got, [0.75, 0.375]);
        let sphere = PrimitiveRecord { a: [0.0; 3], radius: 2.0, ..Default::default() };
        let top = surface_uv(&sphere, &UvRecord::default(), V3::<f64>::new(0.0, 2.0, 0.0));
        assert!(top[1].abs() < 1e-12, "the pole +y is the image's top: {top:?}");
        let side = surface_uv(&sphere, &UvRecord::default(), V3::<f64>::new(2.0, 0.0, 0.0));
        assert!((side[0] - 0.5).abs() < 1e-12 && (side[1] - 0.5).abs() < 1e-12, "{side:?}");
    }
}
