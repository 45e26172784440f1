//! Error metrics and FLIP: analytic values on tiny images, non-finite handling, errors, and
//! LDR-FLIP against NVIDIA's reference implementation (`flip-evaluator` 1.7).

use std::path::PathBuf;

use wavetrace::image_io::{write_exr, RgbImage};
use wavetrace::metrics::{
    compare, flip_map, mean_flip, CompareOptions, CompareReport, ErrorMetrics, MetricsError, DEFAULT_PPD,
};

fn image(width: u32, height: u32, data: Vec<f32>) -> RgbImage {
    RgbImage::from_data(width, height, data).unwrap()
}

fn no_flip() -> CompareOptions {
    CompareOptions { trim: 0.0, flip: false }
}

fn assert_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got - want).abs() <= tol, "{what}: got {got}, want {want} (tolerance {tol})");
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wavetrace-metrics-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---- Analytic values -------------------------------------------------------------------------

/// Two pixels, every channel of the same pixel alike:
/// pixel 0: v = 1.5, r = 1.0; pixel 1: v = 0.0, r = 0.5.
#[test]
fn analytic_values_on_two_pixels() {
    let test = image(2, 1, vec![1.5, 1.5, 1.5, 0.0, 0.0, 0.0]);
    let reference = image(2, 1, vec![1.0, 1.0, 1.0, 0.5, 0.5, 0.5]);
    let m = compare(&test, &reference, &no_flip()).unwrap();

    // MSE = (0.25 + 0.25) / 2.
    assert_close(m.mse, 0.25, 1e-15, "MSE");
    assert_close(m.rmse, 0.5, 1e-15, "RMSE");
    // relMSE (pbrt-v4 MRSE) = (0.25 / 1.01² + 0.25 / 0.51²) / 2.
    assert_close(m.relmse, (0.25 / (1.01f64 * 1.01) + 0.25 / (0.51f64 * 0.51)) / 2.0, 1e-15, "relMSE");
    // SMAPE = (0.5 / 2.5 + 0.5 / 0.5) / 2 = 0.6.
    assert_close(m.smape, 0.6, 1e-15, "SMAPE");
    // MAPE = (0.5 / 1.01 + 0.5 / 0.51) / 2.
    assert_close(m.mape, (0.5 / 1.01 + 0.5 / 0.51) / 2.0, 1e-15, "MAPE");
    assert_eq!((m.pixels, m.non_finite_pixels, m.trimmed_pixels, m.trimmed_fraction), (2, 0, 0, 0.0));
    assert_eq!(m.flip, None);
}

/// Channels are averaged: an error in one channel of one pixel counts 1/3.
#[test]
fn channels_are_averaged() {
    let test = image(1, 1, vec![2.0, 0.0, 0.0]);
    let reference = image(1, 1, vec![0.0, 0.0, 0.0]);
    let m = compare(&test, &reference, &no_flip()).unwrap();
    assert_close(m.mse, 4.0 / 3.0, 1e-15, "MSE");
    assert_close(m.relmse, 4.0 / 0.0001 / 3.0, 1e-9, "relMSE");
    // SMAPE: 2 / 2 = 1 in the red channel, 0/0 := 0 in the others.
    assert_close(m.smape, 1.0 / 3.0, 1e-15, "SMAPE");
    assert_close(m.mape, 2.0 / 0.01 / 3.0, 1e-12, "MAPE");
}

#[test]
fn identical_images_give_zero_everywhere() {
    let data: Vec<f32> = (0..4 * 3 * 3).map(|i| (i as f32 * 0.37).sin().abs() * 3.0).collect();
    let a = image(4, 3, data);
    let m = compare(&a, &a, &CompareOptions::default()).unwrap();
    assert_eq!(
        m,
        ErrorMetrics {
            mse: 0.0,
            rmse: 0.0,
            relmse: 0.0,
            smape: 0.0,
            mape: 0.0,
            flip: Some(0.0),
            non_finite_pixels: 0,
            pixels: 12,
            trimmed_pixels: 0,
            trimmed_fraction: 0.0,
        }
    );
    // All-black images: SMAPE's 0/0 is 0, not NaN.
    let black = RgbImage::new(3, 2);
    let m = compare(&black, &black, &CompareOptions::default()).unwrap();
    assert_eq!([m.mse, m.relmse, m.smape, m.mape, m.flip.unwrap()], [0.0; 5]);
}

// ---- Non-finite pixels, trimming, errors ----------------------------------------------------

#[test]
fn non_finite_pixels_are_counted_and_excluded() {
    // Pixel 0: NaN in the test; pixel 1: +Inf in the reference; pixel 2: -Inf in both;
    // pixel 3: finite, error 0.5 in every channel.
    let test =
        image(4, 1, vec![f32::NAN, 0.0, 0.0, 1.0, 1.0, 1.0, f32::NEG_INFINITY, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let reference =
        image(4, 1, vec![0.0, 0.0, 0.0, 1.0, f32::INFINITY, 1.0, f32::NEG_INFINITY, 0.0, 0.0, 0.5, 0.5, 0.5]);
    let m = compare(&test, &reference, &CompareOptions::default()).unwrap();
    assert_eq!((m.pixels, m.non_finite_pixels), (4, 3));
    assert_close(m.mse, 0.25, 1e-15, "MSE over the one finite pixel");
    assert_close(m.smape, 0.5 / 1.5, 1e-15, "SMAPE");
    for v in [m.mse, m.rmse, m.relmse, m.smape, m.mape, m.flip.unwrap()] {
        assert!(v.is_finite(), "{m:?}");
    }
    // The FLIP map sanitises (NaN -> 0, Inf clamped) rather than propagating NaN.
    assert!(flip_map(&test, &reference).unwrap().iter().all(|v| (0.0..=1.0).contains(v)));

    let nan = image(1, 1, vec![f32::NAN; 3]);
    let err = compare(&nan, &nan, &CompareOptions::default()).unwrap_err();
    assert!(matches!(err, MetricsError::NoFinitePixels { pixels: 1 }), "{err}");
}

#[test]
fn trimming_is_reported() {
    // 1000 pixels with error 0.1, one with error 10: trim 0.001 drops exactly that one.
    let n = 1001;
    let reference = image(n, 1, vec![1.0; 3 * n as usize]);
    let mut data = vec![1.1f32; 3 * n as usize];
    data[1500..1503].copy_from_slice(&[11.0, 11.0, 11.0]);
    let test = image(n, 1, data);
    let untrimmed = compare(&test, &reference, &no_flip()).unwrap();
    assert_eq!((untrimmed.trimmed_pixels, untrimmed.trimmed_fraction), (0, 0.0));
    let m = compare(&test, &reference, &CompareOptions { trim: 0.001, flip: false }).unwrap();
    assert_eq!(m.trimmed_pixels, 1);
    assert_close(m.trimmed_fraction, 1.0 / 1001.0, 1e-15, "trimmed fraction");
    let d = 1.1f32 as f64 - 1.0;
    assert_close(m.mse, d * d, 1e-12, "trimmed MSE");
    assert_close(untrimmed.mse, (1000.0 * d * d + 100.0) / 1001.0, 1e-12, "untrimmed MSE");
}

#[test]
fn size_mismatch_names_both_sizes() {
    let err = compare(&RgbImage::new(4, 3), &RgbImage::new(3, 4), &CompareOptions::default()).unwrap_err();
    assert_eq!(err.to_string(), "image sizes differ: test is 4x3, reference is 3x4");
    let err = flip_map(&RgbImage::new(4, 3), &RgbImage::new(4, 2)).unwrap_err();
    assert!(matches!(err, MetricsError::SizeMismatch { .. }), "{err}");
    let err = compare(&RgbImage::new(0, 3), &RgbImage::new(0, 3), &CompareOptions::default()).unwrap_err();
    assert_eq!(err.to_string(), "images are empty (0x3)");
}

// ---- Files (what `wavetrace compare` reports) -----------------------------------------------

#[test]
fn report_from_files() {
    let dir = temp_dir("report");
    let (a, b, c) = (dir.join("a.exr"), dir.join("b.exr"), dir.join("c.exr"));
    write_exr(&a, &image(2, 1, vec![1.5, 1.5, 1.5, 0.0, 0.0, 0.0]), &[]).unwrap();
    write_exr(&b, &image(2, 1, vec![1.0, 1.0, 1.0, 0.5, 0.5, 0.5]), &[]).unwrap();
    write_exr(&c, &RgbImage::new(3, 2), &[]).unwrap();

    let report = CompareReport::from_files(&a, &b, &CompareOptions::default()).unwrap();
    assert_eq!((report.width, report.height), (2, 1));
    assert_close(report.metrics.smape, 0.6, 1e-15, "SMAPE");
    assert!(report.metrics.flip.is_some());
    let json: serde_json::Value = serde_json::to_value(&report).unwrap();
    assert_eq!(json["schema"], "wavetrace-compare/1");
    assert_eq!(json["metrics"]["mse"], 0.25);
    assert_eq!(json["metrics"]["non_finite_pixels"], 0);
    assert_eq!(json["metrics"]["trimmed_fraction"], 0.0);
    let table = report.table();
    for needle in ["MSE", "relMSE", "SMAPE", "MAPE", "FLIP", "2x1 = 2", "trimming   none", "6.000000e-1"] {
        assert!(table.contains(needle), "{needle:?} not in\n{table}");
    }

    let err = CompareReport::from_files(&a, &c, &CompareOptions::default()).unwrap_err().to_string();
    assert_eq!(
        err,
        format!("image sizes differ: test {} is 2x1, reference {} is 3x2", a.display(), c.display())
    );
    let missing = dir.join("missing.exr");
    let err = CompareReport::from_files(&a, &missing, &CompareOptions::default()).unwrap_err().to_string();
    assert!(err.starts_with("cannot read the reference image: "), "{err}");
    assert!(err.contains(&missing.display().to_string()), "{err}");
    let err =
        CompareReport::from_files(&missing, &b, &CompareOptions { trim: 1.0, flip: false }).unwrap_err();
    assert_eq!(err.to_string(), "trim must be a fraction in [0, 1), got 1", "checked before reading");
    let not_exr = dir.join("not.exr");
    std::fs::write(&not_exr, b"hello").unwrap();
    let err = CompareReport::from_files(&not_exr, &b, &CompareOptions::default()).unwrap_err().to_string();
    assert!(err.starts_with("cannot read the test image: ") && err.contains("not.exr"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---- FLIP against NVIDIA's implementation ---------------------------------------------------

/// An 8-bit sRGB PNG fixture decoded to linear RGB with FLIP's own sRGB curve (in `f32`, as
/// flip-evaluator does with `inputsRGB=True`).
fn load_srgb_png(name: &str) -> RgbImage {
    let path = crate::common::root().join("tests/data").join(name);
    let (width, height, png) = wavetrace::image_io::read_png_rgb8(&path).unwrap_or_else(|e| panic!("{e}"));
    let data = png
        .iter()
        .map(|&b| {
            let c = f32::from(b) / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        })
        .collect();
    image(width, height, data)
}

struct FlipCase {
    test: &'static str,
    reference: &'static str,
    /// flip-evaluator 1.7's mean (`evaluate(...)[1]`, an f32 pooled mean).
    mean: f64,
    /// flip-evaluator's error map at (x, y): corners exercise the clamp-to-edge borders.
    pixels: [((u32, u32), f32); 4],
}

/// From `scripts/flip_reference.py TEST REF --pixels 0,0 31,23 63,47 10,5` (flip-evaluator 1.7,
/// LDR, default 67.02 PPD) on the 64x48 fixtures that `--make-fixtures tests/data` writes.
const FLIP_CASES: [FlipCase; 3] = [
    // Smooth colour gradient vs the same + triangular noise (±0.08 sRGB): colour pipeline.
    FlipCase {
        test: "flip_gradient_noise.png",
        reference: "flip_gradient_ref.png",
        mean: 0.08151271939277649,
        pixels: [
            ((0, 0), 0.084_301_55),
            ((31, 23), 0.050_001_513),
            ((63, 47), 0.249_031_25),
            ((10, 5), 0.038_605_478),
        ],
    },
    // 8-px grey checkerboard vs a 3x3 box blur of it: edge and point features.
    FlipCase {
        test: "flip_checker_blur.png",
        reference: "flip_checker_ref.png",
        mean: 0.21006210148334503,
        pixels: [((0, 0), 0.0), ((31, 23), 0.401_627_5), ((63, 47), 0.0), ((10, 5), 0.212_367_64)],
    },
    // Saturated hue ramp vs a white-balance shift (R x0.88, B x1.12): chromatic channels.
    FlipCase {
        test: "flip_hue_shift.png",
        reference: "flip_hue_ref.png",
        mean: 0.21822983026504517,
        pixels: [
            ((0, 0), 0.164_137_3),
            ((31, 23), 0.228_117_35),
            ((63, 47), 0.419_261_16),
            ((10, 5), 0.153_892),
        ],
    },
];

/// Same algorithm, same f32 operations in the same order: on x86-64 Linux our maps were
/// bit-identical to flip-evaluator's on all 3 × 3072 pixels. What may still differ elsewhere is
/// libm (`expf`, `powf`: ≤ 1 ulp, so ~1e-7 per pixel) and the reference's mean, which it pools in
/// f32 (it differs from the f64 mean of its own map by up to 1.2e-6 here). 1e-5 covers both with
/// margin and is still far below what a wrong constant, border rule or filter tap would change.
const FLIP_MEAN_TOLERANCE: f64 = 1e-5;
const FLIP_PIXEL_TOLERANCE: f32 = 1e-5;

#[test]
fn flip_matches_nvidia_reference() {
    for case in &FLIP_CASES {
        let test = load_srgb_png(case.test);
        let reference = load_srgb_png(case.reference);
        let what = format!("{} vs {}", case.test, case.reference);
        let mean = mean_flip(&test, &reference).unwrap();
        assert_close(mean, case.mean, FLIP_MEAN_TOLERANCE, &format!("mean FLIP, {what}"));
        let map = flip_map(&test, &reference).unwrap();
        for ((x, y), want) in case.pixels {
            let got = map[(y * test.width + x) as usize];
            assert!(
                (got - want).abs() <= FLIP_PIXEL_TOLERANCE,
                "FLIP at ({x}, {y}), {what}: got {got}, want {want}"
            );
        }
        // compare() gives the same mean when every pixel is finite.
        let m = compare(&test, &reference, &CompareOptions::default()).unwrap();
        assert_close(m.flip.unwrap(), mean, 1e-12, "compare().flip");
    }
}

#[test]
fn flip_properties() {
    let (w, h) = (40u32, 30u32);
    let base: Vec<f32> = (0..w * h)
        .flat_map(|i| {
            let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
            [0.2 + 0.6 * x, 0.3 + 0.4 * y, 0.5]
        })
        .collect();
    let reference = image(w, h, base.clone());
    assert_eq!(mean_flip(&reference, &reference).unwrap(), 0.0);
    assert!(flip_map(&reference, &reference).unwrap().iter().all(|&v| v == 0.0));

    // Deterministic ±1 pattern scaled by the noise amplitude: FLIP grows with it, stays in [0, 1].
    let noisy = |amplitude: f32| {
        let data = base
            .iter()
            .enumerate()
            .map(|(i, &v)| v + amplitude * if (i * 7919 + i / 3) % 5 < 2 { 1.0 } else { -1.0 })
            .collect();
        image(w, h, data)
    };
    let mut previous = 0.0;
    for amplitude in [0.01, 0.03, 0.1, 0.3] {
        let map = flip_map(&noisy(amplitude), &reference).unwrap();
        assert!(map.iter().all(|v| (0.0..=1.0).contains(v)));
        let mean = mean_flip(&noisy(amplitude), &reference).unwrap();
        assert!(mean > previous, "FLIP not increasing at amplitude {amplitude}: {mean} <= {previous}");
        previous = mean;
    }

    // HDR values above 1 are clamped: 2.0 and 5.0 both display as white.
    let white2 = image(8, 8, vec![2.0; 192]);
    let white5 = image(8, 8, vec![5.0; 192]);
    assert_eq!(mean_flip(&white2, &white5).unwrap(), 0.0);
    assert!((DEFAULT_PPD - 67.0206).abs() < 1e-3);
}
