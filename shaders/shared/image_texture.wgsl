// Image textures: a surface point's texture coordinates and the bilinear lookup at them; twin of
// src/cpu/image_texture.rs. The texel buffer (`texels`, scene.wgsl) holds the sRGB decoding
// table, a header per image and the texels (src/layout.rs, image_word). Only compiled in where
// TEXTURE_KINDS has TEXTURE_IMAGE: the callers test it before computing coordinates.

// Twin of UvRecord in src/layout.rs: coordinates uv0 at corner a, changing by du along edge b and
// dv along edge c.
struct UvRecord {
    uv0: vec2<f32>,
    du: vec2<f32>,
    dv: vec2<f32>,
}

const IMAGE_HEADERS: u32 = 256u;
const WRAP_REPEAT: u32 = 0u;
const WRAP_CLAMP: u32 = 1u;
const WRAP_MIRROR: u32 = 2u;
// How far from the image a coordinate is followed, in texels (TEXEL_RANGE in Rust).
const TEXEL_RANGE: f32 = 16777216.0;

// The texture coordinates at `p` on primitive `prim` in slot `slot`: a quad's or triangle's from
// its UvRecord at the point's edge coordinates (α, β, as hit_planar finds them), a sphere's
// (φ / 2π, 1 − θ / π) of its outward normal (v = 0 at +y, the image's top).
fn surface_uv(slot: u32, prim: Primitive, p: vec3<f32>) -> vec2<f32> {
    if prim_is(prim.kind, PRIM_SPHERE) {
        let n = (p - prim.a) / prim.radius;
        let phi = atan2(-n.z, n.x) + PI;
        let theta = acos(clamp(-n.y, -1.0, 1.0));
        return vec2<f32>(phi / (2.0 * PI), 1.0 - theta / PI);
    }
    let n = cross(prim.b, prim.c);
    let w = n / dot(n, n);
    let h = p - prim.a;
    let alpha = dot(w, cross(h, prim.c));
    let beta = dot(w, cross(prim.b, h));
    let r = uvs[slot];
    return r.uv0 + r.du * alpha + r.dv * beta;
}

// Texel index `i` of an axis `n` texels long, wrapped by `mode` (GL's REPEAT, CLAMP_TO_EDGE,
// MIRRORED_REPEAT).
fn wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    if mode == WRAP_CLAMP {
        return clamp(i, 0, n - 1);
    }
    if mode == WRAP_MIRROR {
        let period = 2 * n;
        let m = ((i % period) + period) % period;
        return select(m, period - 1 - m, m >= n);
    }
    return ((i % n) + n) % n;
}

// A texel word's linear colour through the decoding table.
fn texel_linear(word: u32) -> vec3<f32> {
    return vec3<f32>(
        bitcast<f32>(texels[word & 0xffu]),
        bitcast<f32>(texels[(word >> 8u) & 0xffu]),
        bitcast<f32>(texels[(word >> 16u) & 0xffu]),
    );
}

// Image material `m` at coordinates `uv`: bilinear in linear space, texel centres at
// (i + 1/2) / size, times the tint (m.color). m.octaves: the image's header index (bits 0..24)
// and its wrap along u (24..26) and v (26..28).
fn image_albedo(m: Material, uv: vec2<f32>) -> vec3<f32> {
    let header = IMAGE_HEADERS + 4u * (m.octaves & 0xffffffu);
    let first = texels[header];
    let size = vec2<u32>(texels[header + 1u], texels[header + 2u]);
    let wrap_u = (m.octaves >> 24u) & 3u;
    let wrap_v = (m.octaves >> 26u) & 3u;
    let xy = clamp(uv * vec2<f32>(size) - 0.5, vec2<f32>(-TEXEL_RANGE), vec2<f32>(TEXEL_RANGE));
    let corner = floor(xy);
    let f = xy - corner;
    let i = vec2<i32>(corner);
    let n = vec2<i32>(size);
    let xa = wrap_index(i.x, n.x, wrap_u);
    let xb = wrap_index(i.x + 1, n.x, wrap_u);
    let ya = wrap_index(i.y, n.y, wrap_v);
    let yb = wrap_index(i.y + 1, n.y, wrap_v);
    let c00 = texel_linear(texels[first + u32(ya * n.x + xa)]);
    let c10 = texel_linear(texels[first + u32(ya * n.x + xb)]);
    let c01 = texel_linear(texels[first + u32(yb * n.x + xa)]);
    let c11 = texel_linear(texels[first + u32(yb * n.x + xb)]);
    let top = c00 * (1.0 - f.x) + c10 * f.x;
    let bottom = c01 * (1.0 - f.x) + c11 * f.x;
    return (top * (1.0 - f.y) + bottom * f.y) * m.color;
}
