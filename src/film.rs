//! Per-pixel sample statistics: the sum and sum of squares of every finite sample, and a count of
//! the NaN/infinite samples that were dropped instead of accumulated. Sums are f64 on the host
//! (the CPU methods add every sample in f64); the GPU film keeps double-float sums
//! (`layout::FilmPixel`), read back here into f64.

use crate::layout::{FilmPixel, FILM_SQ_SCALE};

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelStats {
    pub sum: [f64; 3],
    pub sum_sq: [f64; 3],
    /// Samples accumulated.
    pub count: u32,
    /// Samples dropped for being NaN or infinite.
    pub invalid: u32,
    /// Rays traced by this pixel's paths (closest-hit queries, camera rays included), valid or
    /// not: every method counts them the same way, so rays/s compares across methods.
    pub rays: u64,
}

impl PixelStats {
    #[inline]
    pub fn add(&mut self, v: [f64; 3]) {
        if v.iter().all(|c| c.is_finite()) {
            for (i, c) in v.into_iter().enumerate() {
                self.sum[i] += c;
                self.sum_sq[i] += c * c;
            }
            self.count += 1;
        } else {
            self.invalid += 1;
        }
    }

    pub fn mean(&self) -> [f64; 3] {
        if self.count == 0 {
            return [0.0; 3];
        }
        self.sum.map(|s| s / self.count as f64)
    }

    /// Unbiased variance of the pixel's mean (sample variance / n); 0 with fewer than 2 samples.
    pub fn variance_of_mean(&self) -> [f64; 3] {
        let n = self.count as f64;
        if self.count < 2 {
            return [0.0; 3];
        }
        let m = self.mean();
        std::array::from_fn(|i| ((self.sum_sq[i] / n - m[i] * m[i]).max(0.0) * n / (n - 1.0)) / n)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Samples taken per pixel, valid or not.
    pub spp: u32,
    pub pixels: Vec<PixelStats>,
}

impl Film {
    pub fn new(width: u32, height: u32, spp: u32) -> Self {
        Self { width, height, spp, pixels: vec![PixelStats::default(); (width * height) as usize] }
    }

    /// Reads back the GPU film: each double-float sum as hi + lo in f64 (exact), the squares
    /// unscaled by [`FILM_SQ_SCALE`] (a power of two: exact).
    pub fn from_gpu(width: u32, height: u32, spp: u32, gpu: &[FilmPixel]) -> Self {
        let pixels = gpu
            .iter()
            .map(|p| {
                let join = |hi: [f32; 3], lo: [f32; 3]| std::array::from_fn(|i| hi[i] as f64 + lo[i] as f64);
                let sum_sq: [f64; 3] = join(p.sum_sq_hi, p.sum_sq_lo);
                PixelStats {
                    sum: join(p.sum_hi, p.sum_lo),
                    sum_sq: sum_sq.map(|s| s / FILM_SQ_SCALE),
                    count: spp - p.invalid,
                    invalid: p.invalid,
                    rays: (p.rays_hi as u64) << 32 | p.rays_lo as u64,
                }
            })
            .collect();
        Self { width, height, spp, pixels }
    }

    pub fn pixel(&self, x: u32, y: u32) -> &PixelStats {
        &self.pixels[(y * self.width + x) as usize]
    }

    /// Interleaved RGB means, row-major from the top row, as f32.
    pub fn mean_rgb(&self) -> Vec<f32> {
        self.pixels.iter().flat_map(|p| p.mean().map(|c| c as f32)).collect()
    }

    /// Mean over all pixels and channels.
    pub fn image_mean(&self) -> f64 {
        let total: f64 = self.pixels.iter().map(|p| p.mean().iter().sum::<f64>()).sum();
        total / (3 * self.pixels.len()) as f64
    }

    /// Rays traced over the whole image.
    pub fn rays(&self) -> u64 {
        self.pixels.iter().map(|p| p.rays).sum()
    }

    /// NaN/Inf samples dropped over the whole image.
    pub fn invalid_samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.invalid as u64).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_samples_are_counted_not_accumulated() {
        let mut p = PixelStats::default();
        p.add([1.0, 2.0, 3.0]);
        p.add([f64::NAN, 0.0, 0.0]);
        p.add([3.0, 2.0, f64::INFINITY]);
        p.add([3.0, 4.0, 5.0]);
        assert_eq!(p.count, 2);
        assert_eq!(p.invalid, 2);
        assert_eq!(p.mean(), [2.0, 3.0, 4.0]);
        // Sample variance of {1,3} is 2, so the mean's variance is 1.
        assert!((p.variance_of_mean()[0] - 1.0).abs() < 1e-12);
    }
}
