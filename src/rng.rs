//! Counter-based random numbers shared bit-for-bit with `shaders/shared/rng.wgsl`.
//!
//! Every random number is a pure function of (pixel, sample index, bounce, purpose, seed), so the
//! CPU reference, the megakernel and the wavefront trace the same paths no matter how work is
//! scheduled. The hash is `pcg4d` from Jarzynski & Olano, "Hash Functions for GPU Rendering"
//! (JCGT 2020): integer-only, so Rust and WGSL agree exactly.

/// What a draw is used for; each purpose gets its own independent stream at every bounce.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Purpose {
    /// Pixel jitter (x, y) and lens position (x, y) of the camera ray.
    Camera = 0,
    /// Scattering direction (two numbers) and a discrete choice (one number).
    Scatter = 1,
    /// Next-event estimation: which light (one number) and where on it (two numbers).
    Light = 2,
    /// Russian roulette (`--roulette on`): whether the path goes on (one number). A purpose of
    /// its own, so the draws above are the same with roulette on or off.
    Roulette = 3,
}

/// The pcg4d hash: four 32-bit words in, four well-mixed words out.
#[inline(always)]
pub fn pcg4d(v: [u32; 4]) -> [u32; 4] {
    let [mut x, mut y, mut z, mut w] = v.map(|a| a.wrapping_mul(1_664_525).wrapping_add(1_013_904_223));
    x = x.wrapping_add(y.wrapping_mul(w));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    w = w.wrapping_add(y.wrapping_mul(z));
    x ^= x >> 16;
    y ^= y >> 16;
    z ^= z >> 16;
    w ^= w >> 16;
    x = x.wrapping_add(y.wrapping_mul(w));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    w = w.wrapping_add(y.wrapping_mul(z));
    [x, y, z, w]
}

/// Maps the top 24 bits of a word to [0, 1). Every result is exactly representable in f32 (and
/// f64), so the conversion itself is identical on every device.
#[inline(always)]
pub fn to_unit_f32(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The key of one draw. `bounce` and `purpose` share a word: 24 bits of bounce, 8 of purpose.
#[inline(always)]
pub fn key(pixel: u32, sample: u32, bounce: u32, purpose: Purpose, seed: u32) -> [u32; 4] {
    [pixel, sample, (bounce << 8) | purpose as u32, seed]
}

/// Four uniform numbers in [0, 1) for one (pixel, sample, bounce, purpose, seed).
#[inline(always)]
pub fn uniform4(pixel: u32, sample: u32, bounce: u32, purpose: Purpose, seed: u32) -> [f32; 4] {
    pcg4d(key(pixel, sample, bounce, purpose, seed)).map(to_unit_f32)
}

/// A sequential stream for host-side generation (the built-in scenes' layouts): draw `i` is
/// `pcg4d([i, stream, 0, 0])[0]`, so a layout is fixed by (stream, order of draws).
#[derive(Clone, Debug)]
pub struct Stream {
    stream: u32,
    counter: u32,
}

impl Stream {
    pub fn new(stream: u32) -> Self {
        Self { stream, counter: 0 }
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        let v = pcg4d([self.counter, self.stream, 0, 0])[0];
        self.counter += 1;
        to_unit_f32(v)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_conversion_stays_below_one() {
        assert_eq!(to_unit_f32(0), 0.0);
        assert!(to_unit_f32(u32::MAX) < 1.0);
        assert_eq!(to_unit_f32(u32::MAX), 16_777_215.0 / 16_777_216.0);
    }

    #[test]
    fn purposes_and_bounces_give_different_streams() {
        let a = uniform4(5, 3, 0, Purpose::Camera, 1);
        let b = uniform4(5, 3, 0, Purpose::Scatter, 1);
        let c = uniform4(5, 3, 1, Purpose::Camera, 1);
        let d = uniform4(5, 3, 0, Purpose::Camera, 2);
        let e = uniform4(5, 3, 0, Purpose::Roulette, 1);
        assert_ne!(a, b);
        assert_ne!(e, a);
        assert_ne!(e, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
    }

    #[test]
    fn uniform_mean_and_variance_match_u01() {
        // 4e5 draws: the mean of U(0,1) has standard error 1/sqrt(12 n) ~ 4.6e-4.
        let n = 100_000u32;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for i in 0..n {
            for u in uniform4(i, 7, 2, Purpose::Scatter, 9) {
                s += u as f64;
                s2 += (u as f64) * (u as f64);
            }
        }
        let m = s / (4 * n) as f64;
        let var = s2 / (4 * n) as f64 - m * m;
        assert!((m - 0.5).abs() < 5.0 * 4.6e-4, "mean {m}");
        assert!((var - 1.0 / 12.0).abs() < 2e-3, "variance {var}");
    }
}
