//! Textures: the albedo of a material at a surface point; twin of `shaders/shared/texture.wgsl`.
//! Noise is Perlin gradient noise whose lattice gradients come from hashing the lattice point
//! with the shared pcg4d, so the CPU and the GPU use the same gradients bit for bit.

use super::{real::Real, vec3::V3};
use crate::layout::{texture_kind, MaterialRecord};
use crate::rng::pcg4d;

/// Hash salt of the noise lattice ("nois").
const NOISE_SALT: u32 = 0x6e6f_6973;
/// Hash salts of the value-noise lattice ("valu") and Worley's feature points ("cell").
const VALUE_SALT: u32 = 0x7661_6c75;
const CELL_SALT: u32 = 0x6365_6c6c;

/// The hash of lattice point `i` under `salt` (pcg4d, as the GPU hashes it).
fn lattice_hash(i: [i32; 3], salt: u32) -> [u32; 4] {
    pcg4d([i[0] as u32, i[1] as u32, i[2] as u32, salt])
}

/// A hash word's top 24 bits in [0, 1), exact in f32 (as `shared/rng.wgsl` maps them).
fn unit<T: Real>(h: u32) -> T {
    T::of((h >> 8) as f32 * (1.0 / 16_777_216.0))
}

/// The lattice cell of `p` and `p`'s offset in it.
fn cell_of<T: Real>(p: V3<T>) -> ([i32; 3], V3<T>) {
    let cell = V3::new(p.x.floor(), p.y.floor(), p.z.floor());
    ([cell.x.to_f64() as i32, cell.y.to_f64() as i32, cell.z.to_f64() as i32], p - cell)
}

/// Corner `c` (0..8) of a lattice cube: (c & 1, c >> 1 & 1, c >> 2 & 1).
fn corner(c: u32) -> [i32; 3] {
    [(c & 1) as i32, ((c >> 1) & 1) as i32, ((c >> 2) & 1) as i32]
}

fn corner_f<T: Real>(d: [i32; 3]) -> V3<T> {
    V3::new(T::of(d[0] as f32), T::of(d[1] as f32), T::of(d[2] as f32))
}

/// One of Perlin's 12 edge directions (improved noise), picked by the lattice point's hash.
fn lattice_gradient<T: Real>(i: [i32; 3]) -> V3<T> {
    let h = pcg4d([i[0] as u32, i[1] as u32, i[2] as u32, NOISE_SALT])[0] % 12;
    let a = if h & 1 != 0 { -T::one() } else { T::one() };
    let b = if h & 2 != 0 { -T::one() } else { T::one() };
    let z = T::zero();
    match h >> 2 {
        0 => V3::new(a, b, z),
        1 => V3::new(a, z, b),
        _ => V3::new(z, a, b),
    }
}

/// Gradient noise in about [-1, 1], Hermite-smoothed trilinear as the book's `perlin_interp`.
pub fn perlin<T: Real>(p: V3<T>) -> T {
    let cell = V3::new(p.x.floor(), p.y.floor(), p.z.floor());
    let f = p - cell;
    let i = [cell.x.to_f64() as i32, cell.y.to_f64() as i32, cell.z.to_f64() as i32];
    let (one, three, two) = (T::one(), T::of(3.0), T::of(2.0));
    let smooth = |t: T| t * t * (three - two * t);
    let s = V3::new(smooth(f.x), smooth(f.y), smooth(f.z));
    let mut accum = T::zero();
    for c in 0..8u32 {
        let d = [(c & 1) as i32, ((c >> 1) & 1) as i32, ((c >> 2) & 1) as i32];
        let df = V3::new(T::of(d[0] as f32), T::of(d[1] as f32), T::of(d[2] as f32));
        let w = |d: T, s: T| d * s + (one - d) * (one - s);
        let weight = w(df.x, s.x) * w(df.y, s.y) * w(df.z, s.z);
        let g = lattice_gradient::<T>([i[0] + d[0], i[1] + d[1], i[2] + d[2]]);
        accum = accum + weight * g.dot(f - df);
    }
    accum
}

/// The book's turbulence: |sum of octaves|, each at twice the frequency and half the weight.
pub fn turbulence<T: Real>(p: V3<T>, octaves: u32) -> T {
    let (mut accum, mut q, mut weight) = (T::zero(), p, T::one());
    for _ in 0..octaves {
        accum = accum + weight * perlin(q);
        weight = weight * T::of(0.5);
        q = q * T::of(2.0);
    }
    accum.abs()
}

/// Value noise in [-1, 1): a hashed value per lattice corner, Hermite-smoothed trilinear.
pub fn value_noise<T: Real>(p: V3<T>) -> T {
    let (i, f) = cell_of(p);
    let (one, three, two) = (T::one(), T::of(3.0), T::of(2.0));
    let smooth = |t: T| t * t * (three - two * t);
    let s = V3::new(smooth(f.x), smooth(f.y), smooth(f.z));
    let mut accum = T::zero();
    for c in 0..8u32 {
        let d = corner(c);
        let df = corner_f::<T>(d);
        let w = |d: T, s: T| d * s + (one - d) * (one - s);
        let value =
            two * unit::<T>(lattice_hash([i[0] + d[0], i[1] + d[1], i[2] + d[2]], VALUE_SALT)[0]) - one;
        accum = accum + w(df.x, s.x) * w(df.y, s.y) * w(df.z, s.z) * value;
    }
    accum
}

/// Worley noise over the 8 cells nearest `p` (the 2×2×2 block around the lattice point closest
/// to it), one feature point each: the nearest and second-nearest squared distances.
pub fn worley<T: Real>(p: V3<T>) -> (T, T) {
    let half = T::of(0.5);
    let (i, _) = cell_of(p - V3::new(half, half, half));
    let big = T::of(1e9);
    let (mut f1, mut f2) = (big, big);
    for c in 0..8u32 {
        let d = corner(c);
        let cell = [i[0] + d[0], i[1] + d[1], i[2] + d[2]];
        let h = lattice_hash(cell, CELL_SALT);
        let feature = corner_f::<T>(cell) + V3::new(unit(h[0]), unit(h[1]), unit(h[2]));
        let v = feature - p;
        let d2 = v.dot(v);
        if d2 < f1 {
            f2 = f1;
            f1 = d2;
        } else if d2 < f2 {
            f2 = d2;
        }
    }
    (f1, f2)
}

/// The pattern of texture kind `kind` (a `Pattern`) at `p`, in [0, 1]: each takes `octaves`
/// octaves, every octave hashing the 8 lattice corners around its point once.
pub fn pattern<T: Real>(kind: u32, p: V3<T>, scale: T, octaves: u32) -> T {
    let (zero, one, half, two) = (T::zero(), T::one(), T::of(0.5), T::of(2.0));
    let clamp01 = |x: T| x.max(zero).min(one);
    match kind {
        texture_kind::NOISE => turbulence(p * scale, octaves),
        texture_kind::MARBLE => half * (one + (scale * p.z + T::of(10.0) * turbulence(p, octaves)).sin()),
        texture_kind::WOOD => {
            let q = p * scale;
            let r = (q.x * q.x + q.z * q.z).sqrt() + T::of(2.0) * turbulence(q, octaves);
            T::of(0.3) + T::of(0.7) * half * (one + (T::of(6.283_185_5) * r).sin())
        }
        texture_kind::RIDGED => {
            let (mut accum, mut q, mut weight) = (zero, p * scale, half);
            for _ in 0..octaves {
                let ridge = one - perlin(q).abs();
                accum = accum + weight * ridge * ridge;
                weight = weight * half;
                q = q * two;
            }
            clamp01(accum)
        }
        texture_kind::WARP => {
            let (mut accum, mut q, mut weight) = (zero, p * scale, one);
            for _ in 0..octaves {
                let n = perlin(q);
                accum = accum + weight * n;
                weight = weight * half;
                q = q * two + V3::new(n, -n, n) * T::of(1.7);
            }
            clamp01(half + accum)
        }
        texture_kind::CELLULAR | texture_kind::CRACKLE => {
            let (mut accum, mut q, mut weight) = (zero, p * scale, one);
            for _ in 0..octaves {
                let (f1, f2) = worley(q);
                let v = if kind == texture_kind::CELLULAR { f1.sqrt() } else { f2.sqrt() - f1.sqrt() };
                accum = accum + weight * v;
                weight = weight * half;
                q = q * two;
            }
            clamp01(accum)
        }
        texture_kind::VALUE => {
            let (mut accum, mut q, mut weight) = (zero, p * scale, half);
            for _ in 0..octaves {
                accum = accum + weight * value_noise(q);
                weight = weight * half;
                q = q * two;
            }
            clamp01(half + accum)
        }
        _ => one,
    }
}

/// Where a surface's albedo is looked up: the point (the stress transform undone) for the solid
/// textures, the texture coordinates and the scene's texel buffer for an image.
#[derive(Clone, Copy, Debug)]
pub struct TexturePoint<'a, T> {
    pub p: V3<T>,
    pub uv: [T; 2],
    pub texels: &'a [u32],
}

impl<T: Real> TexturePoint<'static, T> {
    /// A point of a scene without image textures.
    pub fn at(p: V3<T>) -> Self {
        TexturePoint { p, uv: [T::zero(); 2], texels: &[] }
    }
}

/// The albedo of `m` at `at`.
pub fn albedo<T: Real>(m: &MaterialRecord, at: &TexturePoint<T>) -> V3<T> {
    let color = V3::of(m.color);
    let p = at.p;
    match m.texture {
        texture_kind::CHECKER => {
            let s = T::of(m.scale);
            let cell = |x: T| (x / s).floor().to_f64() as i64;
            let parity = (cell(p.x) + cell(p.y) + cell(p.z)) & 1;
            if parity != 0 {
                V3::of(m.color2)
            } else {
                color
            }
        }
        k if texture_kind::is_procedural(k) => color * pattern(k, p, T::of(m.scale), m.octaves),
        texture_kind::IMAGE => super::image_texture::image_albedo(m, at.texels, at.uv),
        _ => color,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> V3<f64> {
        V3::new(x, y, z)
    }

    #[test]
    fn noise_vanishes_on_the_lattice_and_stays_bounded() {
        assert_eq!(perlin(v(3.0, -2.0, 7.0)), 0.0);
        let mut rng = crate::rng::Stream::new(9);
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for _ in 0..20_000 {
            let p = v(
                rng.range(-50.0, 50.0) as f64,
                rng.range(-50.0, 50.0) as f64,
                rng.range(-50.0, 50.0) as f64,
            );
            let n = perlin(p);
            lo = lo.min(n);
            hi = hi.max(n);
        }
        // Improved Perlin noise with edge gradients stays within [-1, 1] and uses the range.
        assert!(lo >= -1.0 && hi <= 1.0 && lo < -0.5 && hi > 0.5, "[{lo}, {hi}]");
    }

    #[test]
    fn noise_is_continuous_across_cells() {
        for x in [0.0, 1.0, -3.0] {
            let (a, b) = (perlin(v(x - 1e-9, 0.3, 0.7)), perlin(v(x + 1e-9, 0.3, 0.7)));
            assert!((a - b).abs() < 1e-6, "{a} vs {b} at x = {x}");
        }
    }

    #[test]
    fn f32_and_f64_agree() {
        let p = [1.37f32, -2.71, 0.42];
        let a = turbulence(V3::<f32>::new(p[0], p[1], p[2]), 7) as f64;
        let b = turbulence(V3::<f64>::new(p[0] as f64, p[1] as f64, p[2] as f64), 7);
        assert!((a - b).abs() < 1e-5, "{a} vs {b}");
    }

    #[test]
    fn checker_alternates_and_solid_ignores_position() {
        let m = MaterialRecord {
            color: [1.0, 1.0, 1.0],
            color2: [0.0, 0.0, 0.0],
            texture: texture_kind::CHECKER,
            scale: 0.5,
            ..Default::default()
        };
        let at = |x, y, z| TexturePoint::at(v(x, y, z));
        assert_eq!(albedo(&m, &at(0.1, 0.1, 0.1)).x, 1.0);
        assert_eq!(albedo(&m, &at(0.6, 0.1, 0.1)).x, 0.0);
        assert_eq!(albedo(&m, &at(-0.1, 0.1, 0.1)).x, 0.0);
        let solid = MaterialRecord { color: [0.2, 0.3, 0.4], ..Default::default() };
        assert_eq!(albedo(&solid, &at(5.0, 1.0, -3.0)).y, 0.3f32 as f64);
    }

    /// Every costly pattern stays in [0, 1] (the book's noise, an unclamped turbulence, in
    /// [0, 2]), varies over space (no pattern degenerates to a
    /// constant), differs from every other, and agrees between f32 and f64.
    #[test]
    fn every_pattern_is_bounded_varied_distinct_and_precision_stable() {
        let mut rng = crate::rng::Stream::new(11);
        let points: Vec<[f32; 3]> =
            (0..2000).map(|_| [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)]).collect();
        let mut all: Vec<Vec<f64>> = Vec::new();
        for kind in texture_kind::NOISE..=texture_kind::VALUE {
            let values: Vec<f64> = points
                .iter()
                .map(|p| {
                    let a = pattern(kind, V3::<f32>::new(p[0], p[1], p[2]), 4.0, 8) as f64;
                    let b = pattern(kind, v(p[0] as f64, p[1] as f64, p[2] as f64), 4.0, 8);
                    assert!((a - b).abs() < 1e-3, "kind {kind} at {p:?}: f32 {a} vs f64 {b}");
                    let top = if kind == texture_kind::NOISE { 2.0 } else { 1.0 };
                    assert!((0.0..=top).contains(&b), "kind {kind} at {p:?}: {b}");
                    b
                })
                .collect();
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            let sd = (values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
            assert!(sd > 0.03, "kind {kind} barely varies: sd {sd}");
            for (other, w) in all.iter().enumerate() {
                let diff =
                    values.iter().zip(w).map(|(a, b)| (a - b).abs()).sum::<f64>() / values.len() as f64;
                assert!(diff > 0.02, "kinds {kind} and {} look alike", other as u32 + texture_kind::NOISE);
            }
            all.push(values);
        }
    }

    #[test]
    fn worley_finds_the_nearest_of_its_cells_feature_points() {
        let (f1, f2) = worley(v(0.3, 1.7, -2.2));
        assert!(f1 > 0.0 && f1 <= f2 && f2 < 3.0, "{f1} {f2}");
    }

    #[test]
    fn more_octaves_add_detail() {
        let p = v(0.3, 0.8, 0.1);
        let one = turbulence(p, 1);
        let eight = turbulence(p, 8);
        assert!(one != eight);
        assert_eq!(turbulence(p, 0), 0.0);
    }
}
