//! Pixel-wise error metrics between a test image and a reference of the same size.
use rayon::prelude::*;

use super::error::check_pair;
use super::{flip, MetricsError};
use crate::image_io::RgbImage;

/// The ε of relMSE and MAPE: keeps near-black reference pixels from dominating.
pub const RELATIVE_EPSILON: f64 = 0.01;

/// What [`compare`] computes besides the always-present metrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareOptions {
    /// Fraction of pixels to drop, per metric, before averaging: the `floor(trim * n)` pixels
    /// with the largest error of that metric (`n` = finite pixels), e.g. 0.001 drops the top
    /// 0.1%. Applies to MSE, RMSE, relMSE, SMAPE and MAPE, not to FLIP. Must be in [0, 1);
    /// default 0 (no trimming). Papers that trim should say so: [`ErrorMetrics`] records it.
    pub trim: f64,
    /// Also compute the mean LDR-FLIP ([`super::mean_flip`]); default true.
    pub flip: bool,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self { trim: 0.0, flip: true }
    }
}

/// Errors of a test image against a reference, each averaged over the three channels of every
/// finite pixel (pixels where either image has a NaN or infinite channel are left out and
/// counted). All means are accumulated in `f64`.
///
/// With `v` the test value and `r` the reference value of one channel:
/// - `mse` = mean((v − r)²); `rmse` = √mse.
/// - `relmse` = mean((v − r)² / (r + 0.01)²): pbrt-v4's MRSE (see [`compare`]).
/// - `smape` = mean(|v − r| / (|v| + |r|)), with 0/0 = 0; in [0, 1].
/// - `mape` = mean(|v − r| / (|r| + 0.01)).
/// - `flip`: mean LDR-FLIP in [0, 1] when requested (never trimmed).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorMetrics {
    pub mse: f64,
    pub rmse: f64,
    pub relmse: f64,
    pub smape: f64,
    pub mape: f64,
    pub flip: Option<f64>,
    /// Pixels left out of every mean because a channel of either image is NaN or ±Inf.
    pub non_finite_pixels: u64,
    /// All pixels of the image (`width * height`), finite or not.
    pub pixels: u64,
    /// Pixels dropped from each trimmed mean (per metric, the largest errors of that metric).
    pub trimmed_pixels: u64,
    /// `trimmed_pixels / (pixels - non_finite_pixels)`: 0 means no trimming was applied.
    pub trimmed_fraction: f64,
}

/// Computes [`ErrorMetrics`] of `test` against `reference`.
///
/// relMSE follows pbrt-v4 exactly: `Image::MRSE` in `src/pbrt/util/image.cpp` (used by
/// `imgtool diff --metric MRSE`) sums `Sqr(v[c] - vref[c]) / Sqr(vref[c] + 0.01)` per channel,
/// i.e. the ε is added to the reference before squaring: `(v − r)² / (r + 0.01)²`. That assumes
/// r ≥ 0, as radiance is; a negative reference near −0.01 would get a huge weight. (pbrt-v4
/// skips infinite terms but divides by all pixels; we leave out non-finite pixels from both.)
///
/// # Errors
/// Sizes differ (the message gives both), `data` does not match its size, the images are empty,
/// every pixel is non-finite, or `opts.trim` is outside [0, 1).
pub fn compare(
    test: &RgbImage,
    reference: &RgbImage,
    opts: &CompareOptions,
) -> Result<ErrorMetrics, MetricsError> {
    check_pair(test, reference)?;
    if !(0.0..1.0).contains(&opts.trim) {
        return Err(MetricsError::InvalidTrim(opts.trim));
    }
    let pixels = test.width as u64 * test.height as u64;
    let row_len = 3 * test.width as usize;

    // Per row, in parallel; rows are then added in order, so the result does not depend on
    // the thread count.
    let rows: Vec<([f64; 4], u64)> = test
        .data
        .par_chunks(row_len)
        .zip(reference.data.par_chunks(row_len))
        .map(|(t, r)| {
            let mut sum = [0.0f64; 4];
            let mut finite = 0u64;
            for (v, r) in t.chunks_exact(3).zip(r.chunks_exact(3)) {
                if let Some(e) = pixel_errors(v, r) {
                    finite += 1;
                    for (s, e) in sum.iter_mut().zip(e) {
                        *s += e;
                    }
                }
            }
            (sum, finite)
        })
        .collect();
    let finite: u64 = rows.iter().map(|(_, n)| n).sum();
    if finite == 0 {
        return Err(MetricsError::NoFinitePixels { pixels });
    }
    let trimmed = (opts.trim * finite as f64).floor() as u64;

    let means = if trimmed == 0 {
        let mut sum = [0.0f64; 4];
        for (row, _) in &rows {
            for (s, r) in sum.iter_mut().zip(row) {
                *s += r;
            }
        }
        sum.map(|s| s / finite as f64)
    } else {
        trimmed_means(test, reference, (finite - trimmed) as usize)
    };

    let flip = if opts.flip {
        let map = flip::flip_map_with_ppd(test, reference, flip::DEFAULT_PPD)?;
        let mut sum = 0.0f64;
        for ((m, t), r) in map.iter().zip(test.data.chunks_exact(3)).zip(reference.data.chunks_exact(3)) {
            if is_finite(t) && is_finite(r) {
                sum += f64::from(*m);
            }
        }
        Some(sum / finite as f64)
    } else {
        None
    };

    let [mse, relmse, smape, mape] = means;
    Ok(ErrorMetrics {
        mse,
        rmse: mse.sqrt(),
        relmse,
        smape,
        mape,
        flip,
        non_finite_pixels: pixels - finite,
        pixels,
        trimmed_pixels: trimmed,
        trimmed_fraction: trimmed as f64 / finite as f64,
    })
}

/// Per-metric means over the `keep` finite pixels with the smallest error of that metric.
fn trimmed_means(test: &RgbImage, reference: &RgbImage, keep: usize) -> [f64; 4] {
    let errors: Vec<[f64; 4]> = test
        .data
        .par_chunks_exact(3)
        .zip(reference.data.par_chunks_exact(3))
        .filter_map(|(v, r)| pixel_errors(v, r))
        .collect();
    let mut means = [0.0f64; 4];
    let mut values = Vec::with_capacity(errors.len());
    for (m, mean) in means.iter_mut().enumerate() {
        values.clear();
        values.extend(errors.iter().map(|e| e[m]));
        // Partition so that values[..keep] are the `keep` smallest (in no particular order).
        values.select_nth_unstable_by(keep, f64::total_cmp);
        *mean = values[..keep].iter().sum::<f64>() / keep as f64;
    }
    means
}

/// Per-pixel (squared error, relative squared error, SAPE, APE), each the mean of the three
/// channels; `None` if a channel of either pixel is not finite.
fn pixel_errors(v: &[f32], r: &[f32]) -> Option<[f64; 4]> {
    if !(is_finite(v) && is_finite(r)) {
        return None;
    }
    let mut e = [0.0f64; 4];
    for (&v, &r) in v.iter().zip(r) {
        let (v, r) = (f64::from(v), f64::from(r));
        let d = v - r;
        let sq = d * d;
        e[0] += sq;
        // pbrt-v4 Image::MRSE: Sqr(v - vref) / Sqr(vref + 0.01). In f64, r (an f32) + 0.01 is
        // never exactly 0, so the term is finite.
        e[1] += sq / ((r + RELATIVE_EPSILON) * (r + RELATIVE_EPSILON));
        let denominator = v.abs() + r.abs();
        e[2] += if denominator > 0.0 { d.abs() / denominator } else { 0.0 };
        e[3] += d.abs() / (r.abs() + RELATIVE_EPSILON);
    }
    Some(e.map(|x| x / 3.0))
}

pub(super) fn is_finite(pixel: &[f32]) -> bool {
    pixel.iter().all(|c| c.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, data: Vec<f32>) -> RgbImage {
        RgbImage::from_data(width, height, data).unwrap()
    }

    #[test]
    fn trimming_drops_the_largest_errors_per_metric() {
        // 10 pixels, one with a huge error: trimming 10% leaves the nine zero-error ones.
        let reference = image(10, 1, vec![0.5; 30]);
        let mut data = vec![0.5; 30];
        data[0..3].copy_from_slice(&[100.0, 100.0, 100.0]);
        let test = image(10, 1, data);
        let opts = CompareOptions { trim: 0.1, flip: false };
        let m = compare(&test, &reference, &opts).unwrap();
        assert_eq!(m.trimmed_pixels, 1);
        assert_eq!(m.trimmed_fraction, 0.1);
        assert_eq!([m.mse, m.relmse, m.smape, m.mape], [0.0; 4]);

        // Fewer pixels than 1/trim: floor(0.05 * 10) = 0, nothing trimmed, and it says so.
        let m = compare(&test, &reference, &CompareOptions { trim: 0.05, flip: false }).unwrap();
        assert_eq!(m.trimmed_pixels, 0);
        assert_eq!(m.trimmed_fraction, 0.0);
        assert!((m.mse - 99.5f64.powi(2) / 10.0).abs() < 1e-9);
    }

    #[test]
    fn invalid_trim_is_rejected() {
        let a = image(1, 1, vec![0.0; 3]);
        for trim in [-0.1, 1.0, f64::NAN] {
            let err = compare(&a, &a, &CompareOptions { trim, flip: false }).unwrap_err();
            assert!(err.to_string().contains("trim"), "{err}");
        }
    }

    #[test]
    fn bad_data_length_is_an_error_not_a_panic() {
        let good = image(2, 1, vec![0.0; 6]);
        let bad = RgbImage { width: 2, height: 1, data: vec![0.0; 5] };
        let err = compare(&bad, &good, &CompareOptions::default()).unwrap_err();
        assert_eq!(err.to_string(), "test image data has 5 values, a 2x1 RGB image needs 6");
    }
}
