//! Statistical comparison of two renders of the same scene (DESIGN.md §4): a per-pixel z-test of
//! means using each pixel's own sample variance, and relative image-mean difference.

use crate::film::Film;

/// Two-sided critical value of the standard normal for significance `alpha`.
pub fn normal_critical(alpha: f64) -> f64 {
    // Inverse of erfc by bisection: accurate to ~1e-12, ample for a test threshold.
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if erfc(mid / std::f64::consts::SQRT_2) > alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Complementary error function (Numerical Recipes' erfcc, relative error < 1.2e-7).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ZTest {
    /// Fraction of pixels whose three channels all pass.
    pub pass_fraction: f64,
    pub failed_pixels: usize,
    /// Relative difference of the image means, |a − b| / b.
    pub mean_rel_diff: f64,
}

/// Per-pixel z-test of means at per-pixel significance `alpha` (Šidák-split over the 3
/// channels). Where both pixels have zero variance the means must agree to 1e-4 relative.
pub fn z_test(a: &Film, b: &Film, alpha: f64) -> ZTest {
    assert_eq!((a.width, a.height), (b.width, b.height), "images differ in size");
    let alpha_channel = 1.0 - (1.0 - alpha).powf(1.0 / 3.0);
    let z_crit = normal_critical(alpha_channel);
    let mut failed = 0;
    for (pa, pb) in a.pixels.iter().zip(&b.pixels) {
        let (ma, mb) = (pa.mean(), pb.mean());
        let (va, vb) = (pa.variance_of_mean(), pb.variance_of_mean());
        let ok = (0..3).all(|c| {
            let var = va[c] + vb[c];
            let d = (ma[c] - mb[c]).abs();
            if var > 0.0 {
                d / var.sqrt() <= z_crit
            } else {
                d <= 1e-4 * ma[c].abs().max(mb[c].abs()).max(1e-6)
            }
        });
        if !ok {
            failed += 1;
        }
    }
    let n = a.pixels.len();
    let (ma, mb) = (a.image_mean(), b.image_mean());
    ZTest {
        pass_fraction: 1.0 - failed as f64 / n as f64,
        failed_pixels: failed,
        mean_rel_diff: (ma - mb).abs() / mb.abs(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::PixelStats;

    #[test]
    fn critical_values_match_tables() {
        assert!((normal_critical(0.05) - 1.959964).abs() < 1e-4);
        assert!((normal_critical(0.01) - 2.575829).abs() < 1e-4);
    }

    fn film_of(values: impl Fn(u32, u32) -> f64, spp: u32) -> Film {
        let mut f = Film::new(8, 8, spp);
        for (i, p) in f.pixels.iter_mut().enumerate() {
            let mut s = PixelStats::default();
            for k in 0..spp {
                let v = values(i as u32, k);
                s.add([v, v, v]);
            }
            *p = s;
        }
        f
    }

    #[test]
    fn z_test_passes_equal_noise_and_fails_a_shift() {
        let noise = |i: u32, k: u32| crate::rng::uniform4(i, k, 0, crate::rng::Purpose::Camera, 0)[0] as f64;
        let a = film_of(noise, 64);
        let b = film_of(|i, k| noise(i, k + 1000), 64);
        let t = z_test(&a, &b, 0.01);
        assert!(t.pass_fraction > 0.9, "{t:?}");
        let shifted = film_of(|i, k| noise(i, k + 1000) + 0.3, 64);
        let t = z_test(&a, &shifted, 0.01);
        assert!(t.pass_fraction < 0.1, "{t:?}");
        assert!(t.mean_rel_diff > 0.3);
    }
}
