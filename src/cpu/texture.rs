//! Textures: the albedo of a material at a surface point; twin of `shaders/shared/texture.wgsl`.
//! Noise is Perlin gradient noise whose lattice gradients come from hashing the lattice point
//! with the shared pcg4d, so the CPU and the GPU use the same gradients bit for bit.

use super::{real::Real, vec3::V3};
use crate::layout::{texture_kind, MaterialRecord};
use crate::rng::pcg4d;

/// Hash salt of the noise lattice ("nois").
const NOISE_SALT: u32 = 0x6e6f_6973;

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

/// The albedo of `m` at `p`.
pub fn albedo<T: Real>(m: &MaterialRecord, p: V3<T>) -> V3<T> {
    let color = V3::of(m.color);
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
        texture_kind::NOISE => color * turbulence(p * T::of(m.scale), m.octaves),
        texture_kind::MARBLE => {
            let phase = T::of(m.scale) * p.z + T::of(10.0) * turbulence(p, m.octaves);
            color * (T::of(0.5) * (T::one() + phase.sin()))
        }
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
        assert_eq!(albedo(&m, v(0.1, 0.1, 0.1)).x, 1.0);
        assert_eq!(albedo(&m, v(0.6, 0.1, 0.1)).x, 0.0);
        assert_eq!(albedo(&m, v(-0.1, 0.1, 0.1)).x, 0.0);
        let solid = MaterialRecord { color: [0.2, 0.3, 0.4], ..Default::default() };
        assert_eq!(albedo(&solid, v(5.0, 1.0, -3.0)).y, 0.3f32 as f64);
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
