//! False-colour maps of per-pixel error, and small previews for the HTML report.

use crate::chart::viridis;
use crate::image_io::{linear_to_srgb8, RgbImage};
use crate::metrics::RELATIVE_EPSILON;

/// The decades the error map spans: relative squared error 1e-4 (dark) to 1 (bright).
pub const MAP_DECADES: (f64, f64) = (-4.0, 0.0);

/// Per pixel, the relative squared error averaged over channels (relMSE's summand,
/// `(v − r)² / (r + 0.01)²`), as log10 mapped from [`MAP_DECADES`] onto viridis, RGB8. Pixels
/// with a non-finite value are drawn magenta.
pub fn relative_error_map(test: &RgbImage, reference: &RgbImage) -> Vec<u8> {
    let mut out = Vec::with_capacity(test.data.len());
    for (v, r) in test.data.chunks_exact(3).zip(reference.data.chunks_exact(3)) {
        let e: f64 = v
            .iter()
            .zip(r)
            .map(|(&v, &r)| {
                let (v, r) = (f64::from(v), f64::from(r));
                (v - r).powi(2) / (r + RELATIVE_EPSILON).powi(2)
            })
            .sum::<f64>()
            / 3.0;
        if !e.is_finite() {
            out.extend_from_slice(&[255, 0, 255]);
            continue;
        }
        let (lo, hi) = MAP_DECADES;
        let t = ((e.max(1e-30).log10() - lo) / (hi - lo)).clamp(0.0, 1.0);
        out.extend_from_slice(&viridis(t as f32));
    }
    out
}

/// The sRGB 8-bit preview of a linear image.
pub fn srgb8(image: &RgbImage) -> Vec<u8> {
    image.data.iter().map(|&v| linear_to_srgb8(v)).collect()
}

/// RGB8 pixels box-filtered down to at most `max_width` wide (aspect kept); unchanged when
/// already small enough. Returns (width, height, pixels).
pub fn downscale(width: u32, height: u32, rgb: &[u8], max_width: u32) -> (u32, u32, Vec<u8>) {
    if width <= max_width {
        return (width, height, rgb.to_vec());
    }
    let factor = width.div_ceil(max_width);
    let (w, h) = (width / factor, (height / factor).max(1));
    let mut out = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0u32; 3];
            let mut n = 0;
            for yy in y * factor..((y + 1) * factor).min(height) {
                for xx in x * factor..(x + 1) * factor {
                    let i = 3 * (yy * width + xx) as usize;
                    for c in 0..3 {
                        sum[c] += u32::from(rgb[i + c]);
                    }
                    n += 1;
                }
            }
            out.extend(sum.map(|s| ((s + n / 2) / n) as u8));
        }
    }
    (w, h, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_images_map_to_the_dark_end_and_large_errors_to_the_bright_end() {
        let r = RgbImage { width: 2, height: 1, data: vec![0.5; 6] };
        let mut t = r.clone();
        t.data[3..].copy_from_slice(&[5.0, 5.0, 5.0]);
        let map = relative_error_map(&t, &r);
        assert_eq!(&map[..3], &viridis(0.0));
        assert_eq!(&map[3..], &viridis(1.0));
        t.data[0] = f32::NAN;
        assert_eq!(&relative_error_map(&t, &r)[..3], &[255, 0, 255]);
    }

    #[test]
    fn downscale_averages_blocks() {
        let rgb: Vec<u8> = [0u8, 0, 0, 100, 100, 100, 10, 10, 10, 30, 30, 30].to_vec();
        let (w, h, out) = downscale(4, 1, &rgb, 2);
        assert_eq!((w, h), (2, 1));
        assert_eq!(out, vec![50, 50, 50, 20, 20, 20]);
        assert_eq!(downscale(4, 1, &rgb, 4).2, rgb);
    }
}
