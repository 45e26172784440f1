//! LDR-FLIP: NVIDIA's perceptual difference metric for alternating images.
//!
//! Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild, "FLIP: A Difference
//! Evaluator for Alternating Images", HPG 2020. This is a port of the LDR path of the official
//! implementation (NVlabs/flip `FLIP.h`, as shipped in the `flip-evaluator` 1.7 package): the same
//! constants, separable filters with clamp-to-edge borders and `f32` arithmetic, so that per-pixel
//! values agree with it to about 1e-6 (checked by `tests/metrics.rs` against values from
//! `scripts/flip_reference.py`).
//!
//! Our images are linear HDR. "FLIP on tonemapped images" means here: exposure 0, clamp each
//! channel to [0, 1] (NaN to 0), sRGB-encode for display. LDR-FLIP's first step decodes sRGB back
//! to linear, so the encode/decode pair is skipped and the clamped linear values go in directly
//! (identical up to rounding, and without 8-bit quantisation). HDR-FLIP (several exposures,
//! ACES tone curve) is not implemented.
//!
//! Pipeline per pixel: linear RGB → YCxCz; colour: contrast-sensitivity filtering (Gaussians in
//! the opponent channels), back to linear RGB clamped to [0, 1], CIELab with Hunt adjustment, HyAB
//! distance, ^0.7 and remapping to [0, 1]; features: edge and point detectors (first and second
//! derivatives of a Gaussian) on the achromatic channel; FLIP = colour^(1 − feature).
use rayon::prelude::*;

use super::error::check_pair;
use super::MetricsError;
use crate::image_io::RgbImage;

/// Pixels per degree of visual angle for an observer `distance_m` from a monitor `width_m` wide
/// showing `width_px` pixels across (FLIP's `calculatePPD`).
pub const fn pixels_per_degree(distance_m: f32, width_px: f32, width_m: f32) -> f32 {
    distance_m * (width_px / width_m) * (PI / 180.0)
}

/// FLIP's standard viewing conditions: 0.7 m from a 0.7 m wide 3840-pixel monitor, ≈ 67.02.
pub const DEFAULT_PPD: f32 = pixels_per_degree(0.7, 3840.0, 0.7);

const PI: f32 = std::f32::consts::PI;
/// Colour-difference exponent, its remapping's breakpoint and value there, edge-detector width
/// (degrees), feature exponent (FLIP's `gqc`, `gpc`, `gpt`, `gw`, `gqf`).
const QC: f32 = 0.7;
const PC: f32 = 0.4;
const PT: f32 = 0.95;
const W: f32 = 0.082;
const QF: f32 = 0.5;
/// Contrast-sensitivity Gaussians `a·√(π/b)·exp(−π²x²/b)` for (Y, Cx, Cz); Cz is a sum of two.
const A1: [f32; 3] = [1.0, 1.0, 34.1];
const B1: [f32; 3] = [0.0047, 0.0053, 0.04];
const A2: [f32; 3] = [0.0, 0.0, 13.5];
const B2: [f32; 3] = [1.0e-5, 1.0e-5, 0.025];
/// D65 reference white in XYZ and its reciprocal (FLIP's `DEFAULT_ILLUMINANT`). The literals are
/// FLIP's, digit for digit, so that they round to the same `f32`.
#[allow(clippy::excessive_precision)]
const WHITE: [f32; 3] = [0.950428545, 1.000000000, 1.088900371];
#[allow(clippy::excessive_precision)]
const INV_WHITE: [f32; 3] = [1.052156925, 1.000000000, 0.918357670];

/// Per-pixel LDR-FLIP of `test` against `reference` at [`DEFAULT_PPD`], row-major, top row
/// first, each in [0, 1]. For false-colour display (e.g. magma) of where the images differ.
///
/// Channels are clamped to [0, 1] first; NaN counts as 0 and +Inf as 1.
///
/// # Errors
/// Sizes differ, `data` does not match its size, or the images are empty.
pub fn flip_map(test: &RgbImage, reference: &RgbImage) -> Result<Vec<f32>, MetricsError> {
    flip_map_with_ppd(test, reference, DEFAULT_PPD)
}

/// Mean of [`flip_map`] over all pixels, accumulated in `f64`: the number FLIP reports.
/// ([`super::compare`] instead averages over the pixels that are finite in both images.)
///
/// # Errors
/// As [`flip_map`].
pub fn mean_flip(test: &RgbImage, reference: &RgbImage) -> Result<f64, MetricsError> {
    let map = flip_map(test, reference)?;
    Ok(map.iter().map(|&v| f64::from(v)).sum::<f64>() / map.len() as f64)
}

/// [`flip_map`] for other viewing conditions (see [`pixels_per_degree`]).
///
/// # Errors
/// As [`flip_map`].
///
/// # Panics
/// If `ppd` is not positive and finite.
pub fn flip_map_with_ppd(test: &RgbImage, reference: &RgbImage, ppd: f32) -> Result<Vec<f32>, MetricsError> {
    check_pair(test, reference)?;
    assert!(ppd.is_finite() && ppd > 0.0, "pixels per degree must be positive, got {ppd}");
    let (w, h) = (test.width as usize, test.height as usize);
    let reference = to_ycxcz(reference);
    let test = to_ycxcz(test);
    let mut map = color_difference(&reference, &test, w, h, ppd);
    apply_feature_difference(&mut map, &reference, &test, w, h, ppd);
    Ok(map)
}

/// Clamped linear RGB → YCxCz (FLIP's `LinearRGBToYCxCz`).
fn to_ycxcz(image: &RgbImage) -> Vec<[f32; 3]> {
    image
        .data
        .par_chunks_exact(3)
        .map(|p| {
            // f32::clamp keeps NaN, so NaN is mapped to 0 first; ±Inf clamp to 1 and 0.
            let rgb = [p[0], p[1], p[2]].map(|c| if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) });
            xyz_to_ycxcz(linear_rgb_to_xyz(rgb))
        })
        .collect()
}

fn linear_rgb_to_xyz([r, g, b]: [f32; 3]) -> [f32; 3] {
    // sRGB primaries, D65 (the fractions are FLIP's).
    const M: [[f32; 3]; 3] = [
        [10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0],
        [2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0],
        [1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0],
    ];
    M.map(|row| row[0] * r + row[1] * g + row[2] * b)
}

fn xyz_to_linear_rgb([x, y, z]: [f32; 3]) -> [f32; 3] {
    #[allow(clippy::excessive_precision)]
    const M: [[f32; 3]; 3] = [
        [3.241003275, -1.537398934, -0.498615861],
        [-0.969224334, 1.875930071, 0.041554224],
        [0.055639423, -0.204011202, 1.057148933],
    ];
    M.map(|row| row[0] * x + row[1] * y + row[2] * z)
}

fn xyz_to_ycxcz(xyz: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = [xyz[0] * INV_WHITE[0], xyz[1] * INV_WHITE[1], xyz[2] * INV_WHITE[2]];
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

fn ycxcz_to_xyz([yy, cx, cz]: [f32; 3]) -> [f32; 3] {
    let y = (yy + 16.0) / 116.0;
    let (cx, cz) = (cx / 500.0, cz / 200.0);
    [(y + cx) * WHITE[0], y * WHITE[1], (y - cz) * WHITE[2]]
}

fn xyz_to_cielab(xyz: [f32; 3]) -> [f32; 3] {
    const DELTA: f32 = 6.0 / 29.0;
    const DELTA_SQUARE: f32 = DELTA * DELTA;
    const DELTA_CUBE: f32 = DELTA * DELTA_SQUARE;
    const FACTOR: f32 = 1.0 / (3.0 * DELTA_SQUARE);
    const TERM: f32 = 4.0 / 29.0;
    let f = |t: f32| if t > DELTA_CUBE { t.powf(1.0 / 3.0) } else { FACTOR * t + TERM };
    let [x, y, z] = [f(xyz[0] * INV_WHITE[0]), f(xyz[1] * INV_WHITE[1]), f(xyz[2] * INV_WHITE[2])];
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// CIELab with the Hunt adjustment: chroma scaled by 0.01·L.
fn hunt_lab(linear_rgb: [f32; 3]) -> [f32; 3] {
    let [l, a, b] = xyz_to_cielab(linear_rgb_to_xyz(linear_rgb));
    [l, 0.01 * l * a, 0.01 * l * b]
}

/// HyAB: city-block distance in L plus Euclidean distance in (a, b).
fn hyab(p: [f32; 3], q: [f32; 3]) -> f32 {
    (p[0] - q[0]).abs() + ((p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2])).sqrt()
}

fn gaussian(x2: f32, a: f32, b: f32) -> f32 {
    a * (PI / b).sqrt() * (-(PI * PI) * x2 / b).exp()
}

/// One factor of a separable 2D Gaussian whose 2D weight is `gaussian` (for Cz's sum of two).
fn gaussian_sqrt(x2: f32, a: f32, b: f32) -> f32 {
    (a * (PI / b).sqrt()).sqrt() * (-(PI * PI) * x2 / b).exp()
}

/// Index `i` clamped to `[0, n)`: the filters' clamp-to-edge border.
#[inline]
fn clamp_index(i: isize, n: usize) -> usize {
    i.clamp(0, n as isize - 1) as usize
}

/// Spatially filtered colour difference per pixel, remapped to [0, 1] (FLIP's
/// `computeColorDifference`).
fn color_difference(reference: &[[f32; 3]], test: &[[f32; 3]], w: usize, h: usize, ppd: f32) -> Vec<f32> {
    let max_b = B1.into_iter().chain(B2).fold(0.0f32, f32::max);
    let radius = (3.0 * (max_b / (2.0 * PI * PI)).sqrt() * ppd).ceil() as usize;
    let width = 2 * radius + 1;
    let dx = 1.0 / ppd;
    // (Y, Cx) taps and the two Cz taps; Y and Cx taps sum to 1, Cz's 2D filter sums to 1.
    let mut ycx = vec![[0.0f32; 2]; width];
    let mut cz = vec![[0.0f32; 2]; width];
    let (mut sum_ycx, mut sum_cz) = ([0.0f32; 2], [0.0f32; 2]);
    for i in 0..width {
        let x = (i as f32 - radius as f32) * dx;
        let x2 = x * x;
        ycx[i] = [gaussian(x2, A1[0], B1[0]), gaussian(x2, A1[1], B1[1])];
        cz[i] = [gaussian_sqrt(x2, A1[2], B1[2]), gaussian_sqrt(x2, A2[2], B2[2])];
        for k in 0..2 {
            sum_ycx[k] += ycx[i][k];
            sum_cz[k] += cz[i][k];
        }
    }
    let norm_cz = 1.0 / (sum_cz[0] * sum_cz[0] + sum_cz[1] * sum_cz[1]).sqrt();
    for i in 0..width {
        ycx[i] = [ycx[i][0] * (1.0 / sum_ycx[0]), ycx[i][1] * (1.0 / sum_ycx[1])];
        cz[i] = [cz[i][0] * norm_cz, cz[i][1] * norm_cz];
    }

    // Horizontal pass: per pixel (Y, Cx, Cz1, Cz2) for both images.
    let horizontal = |image: &[[f32; 3]]| -> Vec<[f32; 4]> {
        let mut out = vec![[0.0f32; 4]; w * h];
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let src = &image[y * w..(y + 1) * w];
            for (x, o) in row.iter_mut().enumerate() {
                let mut acc = [0.0f32; 4];
                for i in 0..width {
                    let p = src[clamp_index(x as isize + i as isize - radius as isize, w)];
                    acc[0] += ycx[i][0] * p[0];
                    acc[1] += ycx[i][1] * p[1];
                    acc[2] += cz[i][0] * p[2];
                    acc[3] += cz[i][1] * p[2];
                }
                *o = acc;
            }
        });
        out
    };
    let (h_ref, h_test) = rayon::join(|| horizontal(reference), || horizontal(test));

    let cmax = hyab(hunt_lab([0.0, 1.0, 0.0]), hunt_lab([0.0, 0.0, 1.0])).powf(QC);
    let pccmax = PC * cmax;
    let mut out = vec![0.0f32; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, o) in row.iter_mut().enumerate() {
            let filtered = |image: &[[f32; 4]]| {
                let mut acc = [0.0f32; 4];
                for i in 0..width {
                    let p = image[clamp_index(y as isize + i as isize - radius as isize, h) * w + x];
                    acc[0] += ycx[i][0] * p[0];
                    acc[1] += ycx[i][1] * p[1];
                    acc[2] += cz[i][0] * p[2];
                    acc[3] += cz[i][1] * p[3];
                }
                let rgb = xyz_to_linear_rgb(ycxcz_to_xyz([acc[0], acc[1], acc[2] + acc[3]]));
                hunt_lab(rgb.map(|c| c.clamp(0.0, 1.0)))
            };
            let difference = hyab(filtered(&h_ref), filtered(&h_test)).powf(QC);
            // Remap: [0, pccmax) → [0, PT), [pccmax, cmax] → [PT, 1].
            *o = if difference < pccmax {
                difference * (PT / pccmax)
            } else {
                PT + ((difference - pccmax) / (cmax - pccmax)) * (1.0 - PT)
            };
        }
    });
    out
}

/// Edge and point feature difference on the achromatic channel, combined with the colour
/// difference already in `map` into the final FLIP value (FLIP's
/// `computeFeatureDifferenceAndFinalError`).
fn apply_feature_difference(
    map: &mut [f32],
    reference: &[[f32; 3]],
    test: &[[f32; 3]],
    w: usize,
    h: usize,
    ppd: f32,
) {
    let sd = 0.5 * W * ppd;
    let radius = (3.0 * sd).ceil() as usize;
    let width = 2 * radius + 1;
    // (Gaussian, 1st derivative, 2nd derivative) taps. The Gaussian sums to 1; the positive and
    // negative taps of each derivative sum to 1 and −1.
    let mut taps = vec![[0.0f32; 3]; width];
    let mut g_sum = 0.0f32;
    let (mut dg_pos, mut dg_neg, mut ddg_pos, mut ddg_neg) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for (i, t) in taps.iter_mut().enumerate() {
        let x = i as f32 - radius as f32;
        let g = (-(x * x) / (2.0 * sd * sd)).exp();
        g_sum += g;
        let dg = -x * g;
        if dg > 0.0 {
            dg_pos += dg;
        } else {
            dg_neg -= dg;
        }
        let ddg = (x * x / (sd * sd) - 1.0) * g;
        if ddg > 0.0 {
            ddg_pos += ddg;
        } else {
            ddg_neg -= ddg;
        }
        *t = [g, dg, ddg];
    }
    for t in &mut taps {
        *t = [
            t[0] / g_sum,
            t[1] / if t[1] > 0.0 { dg_pos } else { dg_neg },
            t[2] / if t[2] > 0.0 { ddg_pos } else { ddg_neg },
        ];
    }

    // Horizontal pass on Y normalised to [0, 1]: (d/dx, d²/dx², Gaussian).
    let horizontal = |image: &[[f32; 3]]| -> Vec<[f32; 3]> {
        let mut out = vec![[0.0f32; 3]; w * h];
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let src = &image[y * w..(y + 1) * w];
            for (x, o) in row.iter_mut().enumerate() {
                let mut acc = [0.0f32; 3];
                for (i, t) in taps.iter().enumerate() {
                    let yy = src[clamp_index(x as isize + i as isize - radius as isize, w)][0];
                    let v = yy * (1.0 / 116.0) + 16.0 / 116.0;
                    acc[0] += t[1] * v;
                    acc[1] += t[2] * v;
                    acc[2] += t[0] * v;
                }
                *o = acc;
            }
        });
        out
    };
    let (h_ref, h_test) = rayon::join(|| horizontal(reference), || horizontal(test));

    let normalization = 1.0 / 2.0f32.sqrt();
    map.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, o) in row.iter_mut().enumerate() {
            // (edge, point) magnitudes.
            let features = |image: &[[f32; 3]]| {
                let (mut dx, mut ddx, mut dy, mut ddy) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
                for (i, t) in taps.iter().enumerate() {
                    let p = image[clamp_index(y as isize + i as isize - radius as isize, h) * w + x];
                    dx += t[0] * p[0];
                    ddx += t[0] * p[1];
                    dy += t[1] * p[2];
                    ddy += t[2] * p[2];
                }
                ((dx * dx + dy * dy).sqrt(), (ddx * ddx + ddy * ddy).sqrt())
            };
            let (edge_ref, point_ref) = features(&h_ref);
            let (edge_test, point_test) = features(&h_test);
            let edge = (edge_ref - edge_test).abs();
            let point = (point_ref - point_test).abs();
            let feature = (normalization * edge.max(point)).powf(QF);
            *o = o.powf(1.0 - feature);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_ppd_is_flips() {
        // flip-evaluator reports ppd 67.02064514160156 for its defaults.
        assert_eq!(DEFAULT_PPD, 67.020_645_f32);
    }

    #[test]
    fn filter_radii_match_flip() {
        // Spatial: ceil(3 * sqrt(0.04 / (2π²)) * 67.02) = 10; feature: ceil(3 * 0.041 * 67.02) = 9.
        let max_b = B1.into_iter().chain(B2).fold(0.0f32, f32::max);
        assert_eq!((3.0 * (max_b / (2.0 * PI * PI)).sqrt() * DEFAULT_PPD).ceil(), 10.0);
        assert_eq!((3.0 * 0.5 * W * DEFAULT_PPD).ceil(), 9.0);
    }

    #[test]
    fn colour_round_trip() {
        for rgb in [[0.2f32, 0.5, 0.9], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]] {
            let back = xyz_to_linear_rgb(ycxcz_to_xyz(xyz_to_ycxcz(linear_rgb_to_xyz(rgb))));
            for (a, b) in rgb.iter().zip(back) {
                assert!((a - b).abs() < 1e-5, "{rgb:?} -> {back:?}");
            }
        }
    }
}
