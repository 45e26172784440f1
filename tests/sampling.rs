//! χ² goodness-of-fit tests of every material's sampling (DESIGN.md §4, after Mitsuba 3 and
//! pbrt-v4): 1e6 scattered directions per case from the CPU reference's `scatter`, binned on the
//! sphere (cosθ × φ in the frame of the normal) against bin probabilities integrated from each
//! material's analytic pdf; discrete outcomes (absorbed; reflect or refract) are cells of their
//! own. Cells expecting fewer than 5 samples are pooled, and each χ² case is one test at α = 0.01
//! Šidák-corrected over all the cases in this file. Negative controls show that the test rejects
//! wrong samplers; deltas (a perfect mirror, the dielectric's two directions, total internal
//! reflection) are checked exactly instead.
//!
//! Run in release: `cargo test --release --test sampling`.

use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::PI;
use wavetrace::cpu::{material::scatter, ray::Ray, real::Real, vec3::V3};
use wavetrace::layout::{material_kind, MaterialRecord};
use wavetrace::rng::{uniform4, Purpose};
use wavetrace::stats::{chi2_test, sidak, Chi2};

const SAMPLES: u32 = 1_000_000;
/// Test-only key of the uniforms ("chi2"), so no render shares these streams.
const SEED: u32 = 0x6368_6932;
const ALPHA: f64 = 0.01;
/// pbrt-v4 and Mitsuba pool cells expecting fewer samples than this.
const MIN_EXPECTED: f64 = 5.0;
/// Bins: cosθ ∈ [-1, 1] × φ ∈ [-π, π) in the frame of the normal (Mitsuba's sphere domain is
/// 80 × 160 too). Equal-area in cosθ, so a uniform density fills them evenly.
const N_Z: usize = 80;
const N_PHI: usize = 160;
const N_BINS: usize = N_Z * N_PHI;
/// Index of the first bin with cosθ ≥ 0: the upper hemisphere is `UPPER..N_BINS`.
const UPPER: usize = N_Z / 2 * N_PHI;
/// A tilted normal, so nothing relies on axis alignment.
const NORMAL: [f64; 3] = [0.3, 0.8, -0.5];

#[derive(Clone, Copy, Debug)]
enum Precision {
    F32,
    F64,
}
use Precision::{F32, F64};

/// Lambertian: (incidence in degrees, arithmetic). The pdf ignores incidence; two are tried anyway.
const LAMBERTIAN: [(f64, Precision); 2] = [(45.0, F64), (80.0, F32)];
/// Metal: (fuzz, incidence in degrees, arithmetic). Fuzz 0 is a delta, tested exactly.
const METAL: [(f32, f64, Precision); 7] = [
    (0.3, 0.0, F64),
    (0.3, 45.0, F64),
    (0.3, 80.0, F64), // the fuzz cone crosses the horizon: part absorbed
    (1.0, 0.0, F64),
    (1.0, 45.0, F64),
    (1.0, 80.0, F64),
    (0.3, 45.0, F32),
];
/// Dielectric: (ior, front face, incidence in degrees, arithmetic), none beyond the critical angle
/// (total internal reflection is tested exactly). ior 1/1.5 is the book's air bubble in glass.
const DIELECTRIC: [(f32, bool, f64, Precision); 9] = [
    (1.5, true, 0.0, F64),
    (1.5, true, 45.0, F64),
    (1.5, true, 80.0, F64),
    (1.5, false, 0.0, F64),
    (1.5, false, 30.0, F64),
    (1.5, false, 40.0, F64), // just below the critical angle, 41.8°
    (1.0 / 1.5, true, 0.0, F64),
    (1.0 / 1.5, true, 30.0, F64),
    (1.5, true, 45.0, F32),
];
/// Every χ² test in this file (the negative controls excluded: they must fail).
const N_TESTS: usize = LAMBERTIAN.len() + METAL.len() + DIELECTRIC.len();

fn alpha_each() -> f64 {
    sidak(ALPHA, N_TESTS)
}

fn material(kind: u32, param: f32) -> MaterialRecord {
    MaterialRecord { color: [0.7, 0.6, 0.5], param, kind, ..Default::default() }
}

/// An orthonormal frame around the normal `n`.
#[derive(Clone, Copy)]
struct Frame {
    t: DVec3,
    b: DVec3,
    n: DVec3,
}

impl Frame {
    fn new(n: DVec3) -> Self {
        let n = n.normalize();
        let (t, b) = n.any_orthonormal_pair();
        Self { t, b, n }
    }

    fn normal() -> Self {
        Self::new(DVec3::from_array(NORMAL))
    }

    fn world(&self, x: f64, y: f64, z: f64) -> DVec3 {
        self.t * x + self.b * y + self.n * z
    }

    /// The ray direction arriving at `theta_deg` from the normal (travelling against it).
    fn incident(&self, theta_deg: f64) -> DVec3 {
        let th = theta_deg.to_radians();
        self.t * th.sin() - self.n * th.cos()
    }

    fn bin(&self, w: DVec3) -> usize {
        let w = w.normalize();
        let z = w.dot(self.n).clamp(-1.0, 1.0);
        let phi = w.dot(self.b).atan2(w.dot(self.t));
        let iz = (((z + 1.0) * 0.5 * N_Z as f64) as usize).min(N_Z - 1);
        let ip = (((phi + PI) / (2.0 * PI) * N_PHI as f64) as usize).min(N_PHI - 1);
        iz * N_PHI + ip
    }

    /// As `bin`, but a scattered direction the sampler put above the surface stays there even if
    /// rounding in this frame puts it a hair below.
    fn bin_upper(&self, w: DVec3) -> usize {
        self.bin(w).max(UPPER)
    }
}

fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

/// Calls `f` with each of the `SAMPLES` outcomes of `scatter` in precision `T` (`None`: absorbed).
/// The uniforms are the renderer's: `uniform4(sample, case, 0, Scatter, SEED)`.
fn scatter_each<T: Real>(
    m: &MaterialRecord,
    d: DVec3,
    n: DVec3,
    front: bool,
    case: u32,
    mut f: impl FnMut(Option<DVec3>),
) {
    let ray = Ray { origin: V3::<T>::splat(T::zero()), dir: V3::of64(d).normalize() };
    let normal = V3::<T>::of64(n).normalize();
    for i in 0..SAMPLES {
        let u = uniform4(i, case, 0, Purpose::Scatter, SEED);
        let s = scatter(m, &ray, V3::splat(T::zero()), normal, front, u);
        f(s.map(|s| DVec3::from_array(s.dir.to_f64())));
    }
}

fn sample(
    p: Precision,
    m: &MaterialRecord,
    d: DVec3,
    n: DVec3,
    front: bool,
    case: u32,
    f: impl FnMut(Option<DVec3>),
) {
    match p {
        F32 => scatter_each::<f32>(m, d, n, front, case, f),
        F64 => scatter_each::<f64>(m, d, n, front, case, f),
    }
}

/// Observed outcomes of one case.
struct Histogram {
    /// Scattered directions per bin (upper hemisphere only, see `Frame::bin_upper`).
    bins: Vec<f64>,
    absorbed: f64,
    /// Directions more than rounding below the surface (there must be none).
    below: usize,
    nonfinite: usize,
}

fn histogram(p: Precision, m: &MaterialRecord, d: DVec3, frame: &Frame, case: u32) -> Histogram {
    let mut h = Histogram { bins: vec![0.0; N_BINS], absorbed: 0.0, below: 0, nonfinite: 0 };
    sample(p, m, d, frame.n, true, case, |s| match s {
        None => h.absorbed += 1.0,
        Some(w) if !w.is_finite() => h.nonfinite += 1,
        Some(w) => {
            if w.dot(frame.n) < -1e-5 {
                h.below += 1;
            }
            h.bins[frame.bin_upper(w)] += 1.0;
        }
    });
    h
}

/// Bin probabilities of a bounded density `pdf` (per steradian) by the midpoint rule on 8 × 8
/// sub-cells of each bin (dω = dcosθ dφ, so the cells are exact in measure). For the pdfs here
/// this adds < 0.1 to a χ² statistic of 1e6 samples (against 32 × 32 sub-cells).
fn integrate_bins(frame: &Frame, pdf: impl Fn(DVec3) -> f64 + Sync) -> Vec<f64> {
    const SUB: usize = 8;
    let dz = 2.0 / (N_Z * SUB) as f64;
    let dphi = 2.0 * PI / (N_PHI * SUB) as f64;
    (0..N_BINS)
        .into_par_iter()
        .map(|k| {
            let (iz, ip) = (k / N_PHI, k % N_PHI);
            let mut sum = 0.0;
            for a in 0..SUB {
                let z = -1.0 + ((iz * SUB + a) as f64 + 0.5) * dz;
                let r = (1.0 - z * z).max(0.0).sqrt();
                for b in 0..SUB {
                    let phi = -PI + ((ip * SUB + b) as f64 + 0.5) * dphi;
                    sum += pdf(frame.world(r * phi.cos(), r * phi.sin(), z));
                }
            }
            sum * dz * dphi
        })
        .collect()
}

/// Bin probabilities of a density given in a parameterization of its own: `point(a, b)` for
/// (a, b) in the unit square returns a direction and the density with respect to da db. The
/// midpoint rule on an `na` × `nb` grid, each point's mass added to the bin it falls in. Used
/// where the density per steradian is singular but smooth in some other parameterization.
fn splat_bins(
    frame: &Frame,
    na: usize,
    nb: usize,
    point: impl Fn(f64, f64) -> (DVec3, f64) + Sync,
) -> Vec<f64> {
    let cell = 1.0 / (na * nb) as f64;
    let mut bins = (0..na)
        .into_par_iter()
        .fold(
            || vec![0.0; N_BINS],
            |mut acc, i| {
                let a = (i as f64 + 0.5) / na as f64;
                for j in 0..nb {
                    let (w, density) = point(a, (j as f64 + 0.5) / nb as f64);
                    acc[frame.bin(w)] += density;
                }
                acc
            },
        )
        .reduce(|| vec![0.0; N_BINS], |a, b| a.iter().zip(&b).map(|(x, y)| x + y).collect());
    bins.iter_mut().for_each(|p| *p *= cell);
    bins
}

fn lambertian_bins(frame: &Frame) -> Vec<f64> {
    let n = frame.n;
    integrate_bins(frame, move |w| w.dot(n).max(0.0) / PI)
}

/// Bin probabilities of normalize(r + f·s), s uniform on the unit sphere, over the whole sphere
/// (before the metal absorbs what points below the surface). The point q = r + f·s is uniform on
/// the sphere of radius f about r (|r| = 1), area density 1/(4πf²). Along the direction ω at angle
/// α from r that sphere is hit at t = cosα ± D, D = sqrt(f² − sin²α), where it is inclined to ω by
/// |cosβ| = D/f, so each hit contributes t²/(4πf²·|cosβ|) = t²/(4πf·D) per steradian:
/// - f ≥ 1 (origin inside): one hit, t = cosα + D: pdf = (cosα + D)²/(4πf·D); f = 1 gives
///   max(cosα, 0)/π, the book's cosine lobe about r.
/// - f < 1 (origin outside): both hits inside the cone sinα < f: pdf = (cos²α + D²)/(2πf·D), which
///   diverges (integrably) at the cone's edge. With sinα = f·sinγ, dω = sinα dα dψ becomes
///   sinγ·f²cosγ/cosα dγ dψ and the singularity cancels: mass (cos²α + D²)·sinγ/(2π·cosα) per
///   dγ dψ, smooth on γ ∈ [0, π/2], ψ ∈ [0, 2π).
fn metal_bins(frame: &Frame, r: DVec3, fuzz: f64) -> Vec<f64> {
    if fuzz >= 1.0 {
        return integrate_bins(frame, move |w| {
            let c = w.dot(r);
            let d = (fuzz * fuzz - 1.0 + c * c).max(0.0).sqrt();
            if c + d <= 0.0 {
                0.0
            } else {
                (c + d) * (c + d) / (4.0 * PI * fuzz * d)
            }
        });
    }
    let (u, v) = r.any_orthonormal_pair();
    // A bin's mass is off by the grid points its edges happen to cut, so the grid is fine (this
    // adds < 0.3 to a χ² statistic of 1e6 samples, against a 4 × 4 finer grid) and ψ has a
    // multiple of N_PHI points: at normal incidence ψ runs along the bins' φ, and 51 or 52 points
    // per bin would be a 2% error.
    splat_bins(frame, 2000, 8000, move |a, b| {
        let (gamma, psi) = (a * PI / 2.0, b * 2.0 * PI);
        let sin_a = fuzz * gamma.sin();
        let cos_a = (1.0 - sin_a * sin_a).sqrt();
        let d = fuzz * gamma.cos();
        let w = r * cos_a + (u * psi.cos() + v * psi.sin()) * sin_a;
        // Density per dγ dψ times the square's Jacobian (π/2)(2π).
        let mass = (cos_a * cos_a + d * d) * gamma.sin() / (2.0 * PI * cos_a) * PI * PI;
        (w, mass)
    })
}

/// Probability that the metal absorbs: r·n + f·(s·n) ≤ 0 with s·n uniform on [-1, 1].
fn metal_absorbed(r: DVec3, n: DVec3, fuzz: f64) -> f64 {
    ((1.0 - r.dot(n) / fuzz) / 2.0).clamp(0.0, 1.0)
}

/// χ² of an upper-hemisphere histogram (plus the absorbed cell) against bin probabilities over
/// the whole sphere (the mass below the surface being the absorbed probability).
fn chi2_directions(name: &str, h: &Histogram, bins: &[f64], absorbed: f64) -> Chi2 {
    assert_eq!(h.nonfinite, 0, "{name}: {} non-finite directions", h.nonfinite);
    assert_eq!(h.below, 0, "{name}: {} directions below the surface", h.below);
    let n = SAMPLES as f64;
    let mut observed = h.bins[UPPER..].to_vec();
    let mut expected: Vec<f64> = bins[UPPER..].iter().map(|p| p * n).collect();
    observed.push(h.absorbed);
    expected.push(absorbed * n);
    let t = chi2_test(&observed, &expected, MIN_EXPECTED);
    eprintln!(
        "{name}: χ² = {:.1}, dof = {}, p = {:.3e} ({} cells pooled, {} samples in empty cells, \
         {:.4} absorbed of {:.4} expected)",
        t.statistic,
        t.dof,
        t.p_value,
        t.pooled_cells,
        t.in_empty_cells,
        h.absorbed / n,
        absorbed
    );
    t
}

/// Asserts every case passed at the Šidák-corrected level (after printing them all).
fn assert_all_pass(results: &[(String, Chi2)]) {
    let a = alpha_each();
    let failed: Vec<_> = results.iter().filter(|(_, t)| t.p_value.is_nan() || t.p_value < a).collect();
    assert!(failed.is_empty(), "χ² rejects at α' = {a:.3e} (α = {ALPHA}, {N_TESTS} tests): {failed:?}");
}

#[test]
fn lambertian_is_cosine_weighted() {
    let frame = Frame::normal();
    let expected = lambertian_bins(&frame);
    let upper: f64 = expected[UPPER..].iter().sum();
    assert!((upper - 1.0).abs() < 1e-9 && expected[..UPPER].iter().all(|&p| p == 0.0), "{upper}");
    let m = material(material_kind::LAMBERTIAN, 0.0);
    let results: Vec<_> = LAMBERTIAN
        .iter()
        .enumerate()
        .map(|(i, &(theta, p))| {
            let name = format!("lambertian {theta}° {p:?}");
            let h = histogram(p, &m, frame.incident(theta), &frame, i as u32);
            assert_eq!(h.absorbed, 0.0, "{name}: a lambertian never absorbs");
            (name.clone(), chi2_directions(&name, &h, &expected, 0.0))
        })
        .collect();
    assert_all_pass(&results);
}

#[test]
fn fuzzy_metal_matches_its_lobe_and_absorption() {
    let frame = Frame::normal();
    let results: Vec<_> = METAL
        .iter()
        .enumerate()
        .map(|(i, &(fuzz, theta, p))| {
            let name = format!("metal fuzz {fuzz} {theta}° {p:?}");
            let d = frame.incident(theta);
            let r = reflect(d, frame.n);
            let expected = metal_bins(&frame, r, fuzz as f64);
            let absorbed = metal_absorbed(r, frame.n, fuzz as f64);
            // The pdf's derivation checks itself: it integrates to 1, and its mass below the
            // surface equals the absorption computed independently from s·n.
            let (lower, upper): (f64, f64) = (expected[..UPPER].iter().sum(), expected[UPPER..].iter().sum());
            assert!((lower + upper - 1.0).abs() < 1e-6, "{name}: pdf integrates to {}", lower + upper);
            assert!((lower - absorbed).abs() < 1e-3, "{name}: {lower} below the surface vs {absorbed}");
            let h = histogram(p, &material(material_kind::METAL, fuzz), d, &frame, 100 + i as u32);
            (name.clone(), chi2_directions(&name, &h, &expected, absorbed))
        })
        .collect();
    assert_all_pass(&results);
}

#[test]
fn perfect_metal_is_an_exact_mirror() {
    let frame = Frame::normal();
    let m = material(material_kind::METAL, 0.0);
    for p in [F32, F64] {
        let tol = match p {
            F32 => 1e-6,
            F64 => 1e-14,
        };
        for theta in [0.0, 45.0, 80.0, 89.0] {
            let d = frame.incident(theta);
            let r = reflect(d, frame.n);
            let mut worst = 0.0f64;
            sample(p, &m, d, frame.n, true, 150, |s| {
                let w = s.unwrap_or_else(|| panic!("mirror at {theta}° absorbed"));
                worst = worst.max((w - r).length());
            });
            assert!(worst <= tol, "mirror {p:?} {theta}°: off by {worst:e}");
        }
    }
}

/// Schlick's reflectance as the book writes it: the cosine of the incident side, whichever
/// medium that is.
fn schlick(cos_i: f64, ior: f64) -> f64 {
    let r0 = ((1.0 - ior) / (1.0 + ior)).powi(2);
    r0 + (1.0 - r0) * (1.0 - cos_i).powi(5)
}

/// Exact unpolarised Fresnel reflectance going from index 1 into relative index `eta`
/// (for the negative control).
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Reflected and refracted counts of one dielectric case, every direction checked exactly
/// against the law of reflection and Snell's law.
fn dielectric_counts(p: Precision, ior: f32, front: bool, theta: f64, case: u32) -> (f64, f64) {
    let frame = Frame::normal();
    let (d, n) = (frame.incident(theta), frame.n);
    let ri = if front { 1.0 / ior as f64 } else { ior as f64 };
    let cos_i = -d.dot(n);
    let mirror = reflect(d, n);
    // Snell: the tangential part scales by ri, the normal part makes the direction unit length.
    let tangential = (d + n * cos_i) * ri;
    let cos_t2 = 1.0 - tangential.length_squared();
    let refracted = (cos_t2 >= 0.0).then(|| tangential - n * cos_t2.sqrt());
    let tol = match p {
        F32 => 1e-5,
        F64 => 1e-12,
    };
    let (mut reflected, mut transmitted) = (0.0, 0.0);
    let m = material(material_kind::DIELECTRIC, ior);
    sample(p, &m, d, n, front, case, |s| {
        let w = s.expect("a dielectric never absorbs");
        if w.dot(n) > 0.0 {
            let err = (w - mirror).length();
            assert!(err <= tol, "ior {ior} {theta}°: reflection off the mirror direction by {err:e}");
            reflected += 1.0;
        } else {
            let t =
                refracted.unwrap_or_else(|| panic!("ior {ior} {theta}°: refraction past the critical angle"));
            let err = (w - t).length();
            assert!(err <= tol, "ior {ior} {theta}°: refraction off Snell's direction by {err:e}");
            transmitted += 1.0;
        }
    });
    (reflected, transmitted)
}

fn chi2_two_outcomes(name: &str, (reflected, transmitted): (f64, f64), p_reflect: f64) -> Chi2 {
    let n = SAMPLES as f64;
    let t = chi2_test(&[reflected, transmitted], &[p_reflect * n, (1.0 - p_reflect) * n], MIN_EXPECTED);
    eprintln!(
        "{name}: χ² = {:.2}, dof = {}, p = {:.3e} (reflected {:.5}, expected {:.5})",
        t.statistic,
        t.dof,
        t.p_value,
        reflected / n,
        p_reflect
    );
    t
}

#[test]
fn dielectric_chooses_by_schlick_and_obeys_snell() {
    let results: Vec<_> = DIELECTRIC
        .iter()
        .enumerate()
        .map(|(i, &(ior, front, theta, p))| {
            let name =
                format!("dielectric ior {ior:.4} {} {theta}° {p:?}", if front { "front" } else { "back" });
            let counts = dielectric_counts(p, ior, front, theta, 200 + i as u32);
            let expected = schlick(theta.to_radians().cos(), ior as f64);
            (name.clone(), chi2_two_outcomes(&name, counts, expected))
        })
        .collect();
    assert_all_pass(&results);
}

#[test]
fn dielectric_reflects_totally_beyond_the_critical_angle() {
    // Leaving glass at 45° and entering the book's bubble (ior 1/1.5) at 60°: sin θ · 1.5 > 1.
    for (ior, front, theta) in [(1.5f32, false, 45.0), (1.0 / 1.5, true, 60.0), (1.5, false, 89.0)] {
        for p in [F32, F64] {
            let (reflected, transmitted) = dielectric_counts(p, ior, front, theta, 250);
            assert_eq!((reflected, transmitted), (SAMPLES as f64, 0.0), "ior {ior} {theta}° {p:?}");
        }
    }
}

#[test]
fn emitters_never_scatter() {
    let frame = Frame::normal();
    let m = material(material_kind::EMISSIVE, 0.0);
    for p in [F32, F64] {
        sample(p, &m, frame.incident(30.0), frame.n, true, 260, |s| assert!(s.is_none()));
    }
}

/// Without these a passing χ² test proves nothing: wrong samplers, or right samplers against a
/// wrong pdf, must be rejected far beyond any Šidák threshold.
#[test]
fn chi2_rejects_wrong_samplers() {
    let frame = Frame::normal();
    let n = SAMPLES as f64;
    let mut results = Vec::new();
    let own = |sampler: &dyn Fn([f32; 4]) -> DVec3, case: u32| {
        let mut h = Histogram { bins: vec![0.0; N_BINS], absorbed: 0.0, below: 0, nonfinite: 0 };
        for i in 0..SAMPLES {
            h.bins[frame.bin_upper(sampler(uniform4(i, case, 0, Purpose::Scatter, SEED)))] += 1.0;
        }
        h
    };
    let cosine = lambertian_bins(&frame);
    // Uniform hemisphere directions against the cosine pdf.
    let uniform = own(
        &|u| {
            let z = u[0] as f64;
            let (r, phi) = ((1.0 - z * z).sqrt(), 2.0 * PI * u[1] as f64);
            frame.world(r * phi.cos(), r * phi.sin(), z)
        },
        300,
    );
    results.push((
        "uniform hemisphere vs cosine",
        chi2_directions("control: uniform hemisphere", &uniform, &cosine, 0.0),
    ));
    // The book's first diffuse model: normal + a point inside the unit ball, not on the sphere.
    let ball = own(
        &|u| {
            let z = 1.0 - 2.0 * u[0] as f64;
            let (r, phi) = ((1.0 - z * z).sqrt(), 2.0 * PI * u[1] as f64);
            let s = DVec3::new(r * phi.cos(), r * phi.sin(), z) * (u[2] as f64).cbrt();
            (frame.n + s).normalize()
        },
        301,
    );
    results.push((
        "normal + in-ball vs cosine",
        chi2_directions("control: normal + in unit ball", &ball, &cosine, 0.0),
    ));
    // Metal fuzz 0.3 at 80° against the pdf of fuzz 0.303, 1% off (even 0.3% gives χ² ≈ 3000
    // on ~340 dof at 45°: the lobe's sharp edge moves across bins).
    let d = frame.incident(80.0);
    let r = reflect(d, frame.n);
    let h = histogram(F64, &material(material_kind::METAL, 0.3), d, &frame, 302);
    let wrong = metal_bins(&frame, r, 0.303);
    results.push((
        "metal fuzz 0.3 vs 0.303",
        chi2_directions(
            "control: metal fuzz 0.3 vs pdf of 0.303",
            &h,
            &wrong,
            metal_absorbed(r, frame.n, 0.303),
        ),
    ));
    // Schlick's approximation against exact Fresnel at 80° into glass (0.412 vs 0.388).
    let counts = dielectric_counts(F64, 1.5, true, 80.0, 303);
    let exact = fresnel(80f64.to_radians().cos(), 1.5);
    results.push((
        "Schlick vs exact Fresnel",
        chi2_two_outcomes("control: Schlick vs exact Fresnel", counts, exact),
    ));
    for (name, t) in &results {
        assert!(t.p_value < 1e-12, "{name}: the χ² test failed to reject (p = {:e}, n = {n})", t.p_value);
    }
}
