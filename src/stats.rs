//! Statistical comparison of two renders of the same scene (DESIGN.md §4): a per-pixel z-test of
//! means using each pixel's own sample variance, and relative image-mean difference. Also Pearson's
//! χ² goodness-of-fit test (with the χ² survival function) for the sampling tests. The special
//! functions and distributions come from `statrs`; what is ours is how renders are compared.

use crate::film::Film;

/// The median of `sorted` (ascending, not empty): the middle value, or the mean of the middle
/// two.
pub fn median_of_sorted(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// Two-sided critical value of the standard normal for significance `alpha`.
pub fn normal_critical(alpha: f64) -> f64 {
    assert!(alpha > 0.0 && alpha < 1.0, "alpha = {alpha}");
    // Upper quantile through erfc⁻¹ directly: 1 − α/2 would round away tiny alphas.
    std::f64::consts::SQRT_2 * statrs::function::erf::erfc_inv(alpha)
}

/// Complementary error function.
pub use statrs::function::erf::erfc;

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

/// Šidák-corrected per-test significance: `n` independent tests at `alpha_each` reject a true
/// hypothesis with overall probability `alpha`.
pub fn sidak(alpha: f64, n: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / n as f64)
}

/// ln Γ(x) for x > 0.
pub use statrs::function::gamma::ln_gamma;

/// Survival function of the χ² distribution with `dof` degrees of freedom: P(X ≥ x).
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    assert!(dof > 0, "χ² needs at least one degree of freedom");
    if x <= 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    // The regularised upper incomplete gamma: no 1 − cdf, so far tails keep their precision.
    statrs::function::gamma::gamma_ur(0.5 * dof as f64, 0.5 * x)
}

/// Outcome of Pearson's χ² goodness-of-fit test.
#[derive(Clone, Debug, PartialEq)]
pub struct Chi2 {
    pub statistic: f64,
    /// Cells after pooling, minus one.
    pub dof: usize,
    pub p_value: f64,
    /// Cells merged into the pool (expected count below the threshold).
    pub pooled_cells: usize,
    /// Observations in cells of expected count exactly 0 (they go to the pool).
    pub in_empty_cells: f64,
}

/// Pearson's χ² test of `observed` counts against `expected` counts (same cells). As pbrt-v4 and
/// Mitsuba do, cells expecting fewer than `min_expected` are pooled into one cell (adding the next
/// larger ones while the pool is still below the threshold), so the χ² approximation holds. The
/// expected counts are not renormalised: a wrong total is part of what is tested.
pub fn chi2_test(observed: &[f64], expected: &[f64], min_expected: f64) -> Chi2 {
    assert_eq!(observed.len(), expected.len(), "cells differ");
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut stat, mut cells, mut pooled, mut in_empty) = (0.0, 0usize, 0usize, 0.0);
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for &i in &order {
        let (o, e) = (observed[i], expected[i]);
        if e == 0.0 {
            in_empty += o;
        }
        if e < min_expected || (pooled > 0 && pool_exp < min_expected) {
            pool_obs += o;
            pool_exp += e;
            pooled += 1;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pooled > 0 {
        if pool_exp > 0.0 {
            stat += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        } else if pool_obs > 0.0 {
            stat = f64::INFINITY; // observations where none can occur
        }
        cells += 1;
    }
    let dof = cells.saturating_sub(1).max(1);
    Chi2 { statistic: stat, dof, p_value: chi2_sf(stat, dof), pooled_cells: pooled, in_empty_cells: in_empty }
}

/// P(X ≥ k) for X ~ Binomial(n, p): how surprising `k` failed pixel tests out of `n` are when
/// each fails with probability `p` by chance. Two independent renders of a true match fail about
/// α·n per-pixel z-tests, so "at least 99% pass at α = 0.01" would fail half the time; tests of
/// independent images bound the failures by this tail instead.
pub fn binomial_tail(n: usize, k: usize, p: f64) -> f64 {
    use statrs::distribution::{Binomial, DiscreteCDF};
    if k == 0 {
        return 1.0;
    }
    // P(X ≥ k) = P(X > k − 1): statrs' survival function is the regularised incomplete beta.
    Binomial::new(p, n as u64).expect("0 ≤ p ≤ 1").sf(k as u64 - 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::PixelStats;

    #[test]
    fn critical_values_match_tables() {
        assert!((normal_critical(0.05) - 1.959964).abs() < 1e-4);
        assert!((normal_critical(0.01) - 2.575829).abs() < 1e-4);
        // Šidák-split alphas get tiny: the quantile must not round 1 − α/2 to 1.
        assert!((normal_critical(1e-9) - 6.109410).abs() < 1e-4);
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

    #[test]
    fn chi2_survival_matches_tables() {
        // Textbook critical values (5% and 1%) and closed forms for 2 and 4 dof.
        let close = |a: f64, b: f64, tol: f64| assert!((a - b).abs() <= tol, "{a} vs {b}");
        close(chi2_sf(3.841_458_820_694_124, 1), 0.05, 1e-8);
        close(chi2_sf(6.634_896_601_021_214, 1), 0.01, 1e-8);
        close(chi2_sf(18.307_038_053_275_146, 10), 0.05, 1e-8);
        close(chi2_sf(23.209_251_158_954_356, 10), 0.01, 1e-8);
        close(chi2_sf(124.342, 100), 0.05, 2e-5); // table value, 3 decimals
        for x in [0.1, 1.0, 2.0, 7.5, 40.0] {
            close(chi2_sf(x, 2), (-x / 2.0).exp(), 1e-13);
            close(chi2_sf(x, 4), (-x / 2.0).exp() * (1.0 + x / 2.0), 1e-13);
        }
        for k in [1, 2, 7, 100, 10_000] {
            assert_eq!(chi2_sf(0.0, k), 1.0);
        }
        // Far upper tail keeps relative precision (continued fraction): sf(x, 2) = e^{-x/2}.
        let t = chi2_sf(1000.0, 2);
        assert!((t / (-500.0f64).exp() - 1.0).abs() < 1e-10, "{t}");
        // Large k: the Wilson–Hilferty approximation is accurate to ~1e-5 at k = 10⁴.
        let k = 10_000usize;
        for x in [9_700.0, 10_000.0, 10_300.0, 10_500.0] {
            let kf = k as f64;
            let z = ((x / kf).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * kf))) / (2.0 / (9.0 * kf)).sqrt();
            close(chi2_sf(x, k), 0.5 * erfc(z / std::f64::consts::SQRT_2), 1e-4);
        }
        // Monotone in x.
        assert!(chi2_sf(3199.0, 3199) > chi2_sf(3400.0, 3199));
    }

    #[test]
    fn ln_gamma_matches_factorials() {
        let mut f = 1.0f64;
        for n in 1..30 {
            assert!((ln_gamma(n as f64) - f.ln()).abs() < 1e-12 * f.ln().max(1.0), "Γ({n})");
            f *= n as f64;
        }
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-14);
    }

    #[test]
    fn chi2_test_pools_small_cells_and_catches_a_bias() {
        // Exact fit: statistic 0, p = 1. Three cells below 5 pool with the next one (3+1+0.5+10).
        let e = [3.0, 1.0, 0.5, 10.0, 100.0, 100.0];
        let t = chi2_test(&e, &e, 5.0);
        assert_eq!((t.statistic, t.pooled_cells, t.dof), (0.0, 4, 2));
        assert_eq!(t.p_value, 1.0);
        // Observations in a cell that expects none count against the fit.
        let t = chi2_test(&[0.0, 100.0, 100.0], &[0.0, 100.0, 100.0], 5.0);
        assert_eq!(t.in_empty_cells, 0.0);
        let t = chi2_test(&[2.0, 100.0, 98.0], &[0.0, 100.0, 100.0], 5.0);
        assert_eq!(t.in_empty_cells, 2.0);
        // A 10% excess in one of two big cells is far beyond chance.
        let t = chi2_test(&[11_000.0, 9_000.0], &[10_000.0, 10_000.0], 5.0);
        assert!((t.statistic - 200.0).abs() < 1e-9 && t.dof == 1 && t.p_value < 1e-40, "{t:?}");
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
        assert!((1.0 - (1.0 - sidak(0.01, 18)).powi(18) - 0.01).abs() < 1e-12);
    }

    #[test]
    fn binomial_tail_matches_hand_values() {
        assert_eq!(binomial_tail(10, 0, 0.3), 1.0);
        // P(X >= 1) = 1 - 0.7^10.
        assert!((binomial_tail(10, 1, 0.3) - (1.0 - 0.7f64.powi(10))).abs() < 1e-12);
        // P(X = 10) = 0.3^10.
        assert!((binomial_tail(10, 10, 0.3) - 0.3f64.powi(10)).abs() < 1e-15);
        assert_eq!(binomial_tail(10, 11, 0.3), 0.0);
        // 256 tests at 1%: 5 failures is unremarkable, 12 is not.
        assert!(binomial_tail(256, 5, 0.01) > 0.05);
        assert!(binomial_tail(256, 12, 0.01) < 1e-4);
    }
}
