//! The film keeps its precision and cannot overflow where a plain f32 film would: a pixel of a
//! constant scene summed over 2^20 samples comes out exact on every method (CPU sums in f64, the
//! GPU in double-float), and samples whose squares pass f32's range leave a finite variance.

use crate::common;

use glam::Vec3;
use wavetrace::film::Film;
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::{Background, CameraSpec, Scene};
use wavetrace::settings::{Accel, RenderSettings};

const METHODS: [Method; 4] = [Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront];

/// No objects: every camera ray sees `background`, so every sample is exactly that value.
fn constant(background: Vec3) -> Scene {
    Scene {
        name: "constant".into(),
        camera: CameraSpec {
            lookfrom: Vec3::ZERO,
            lookat: Vec3::NEG_Z,
            vup: Vec3::Y,
            vfov: 40.0,
            defocus_angle: 0.0,
            focus_dist: 1.0,
        },
        background: Background::Constant(background),
        materials: Vec::new(),
        spheres: Vec::new(),
        quads: Vec::new(),
        meshes: Vec::new(),
        images: Vec::new(),
    }
}

fn one_pixel(spp: u32) -> RenderSettings {
    RenderSettings {
        width: 1,
        height: 1,
        spp,
        max_depth: 4,
        seed: 0,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

fn films(scene: &Scene, s: &RenderSettings) -> Vec<(Method, Film)> {
    METHODS
        .into_iter()
        .filter(|m| !m.needs_gpu() || common::gpu().is_some())
        .map(|m| (m, render(m, scene, s, &MethodOptions::default(), common::gpu(), &|_| {}).unwrap().film))
        .collect()
}

/// The mean a film summing in plain f32 (as the GPU film did) reports for `n` samples of `v`.
fn plain_f32_mean(v: f32, n: u32) -> f64 {
    let mut sum = 0.0f32;
    for _ in 0..n {
        sum += v;
    }
    sum as f64 / n as f64
}

/// 2^20 samples of 0.1, 0.3 and 0.7 in one pixel: every method's mean is the sample value exactly
/// (2^20 · v needs 44 bits, which f64 and a double-float hold), and its variance is zero to f32
/// rounding of the squares. A plain f32 sum is off by about 1% here (checked below, so the test
/// can fail).
#[test]
fn a_constant_pixel_is_exact_after_2_20_samples() {
    let n = 1u32 << 20;
    let v = Vec3::new(0.1, 0.3, 0.7);
    for c in v.to_array() {
        let plain = plain_f32_mean(c, n);
        assert!((plain / c as f64 - 1.0).abs() > 1e-4, "a plain f32 sum of {c} gives {plain}");
    }
    for (method, film) in films(&constant(v), &one_pixel(n)) {
        let p = film.pixel(0, 0);
        assert_eq!((p.count, p.invalid), (n, 0));
        assert_eq!(p.rays, n as u64, "{}: one ray per sample", method.name());
        let want = v.to_array().map(|c| c as f64);
        assert_eq!(p.mean(), want, "{}: the mean of 2^20 equal samples", method.name());
        let var = p.variance_of_mean();
        for i in 0..3 {
            // E[x²] within f32 rounding of x²: variance of the mean below x² · 2^-23 / n.
            let bound = want[i] * want[i] * f32::EPSILON as f64 / n as f64;
            assert!(var[i] <= bound, "{}: variance of the mean {} > {bound}", method.name(), var[i]);
        }
    }
}

/// Samples of 1e20 (squares of 1e40, past f32's 3.4e38): the mean is exact and the variance
/// finite (zero to rounding) on every method. A plain f32 sum of squares is infinite here.
#[test]
fn squares_past_f32s_range_leave_a_finite_variance() {
    let v = 1e20f32;
    assert!((v * v).is_infinite());
    let n = 1000;
    for (method, film) in films(&constant(Vec3::splat(v)), &one_pixel(n)) {
        let p = film.pixel(0, 0);
        assert_eq!(p.mean(), [v as f64; 3], "{}", method.name());
        for var in p.variance_of_mean() {
            let bound = (v as f64).powi(2) * f32::EPSILON as f64 / n as f64;
            assert!(var.is_finite() && var <= bound, "{}: variance of the mean {var}", method.name());
        }
    }
}

/// A long pixel of varying samples (one straddling an edge: 2^20 samples, 256 dispatches of
/// 4096 on the GPU methods) comes out bit-identical on repeat, and with the mean the CPU's f64 sum
/// of the same f32 samples gives, up to the few samples near the edge that rounding sends the other
/// way on the GPU.
#[test]
fn a_long_pixel_of_an_edge_keeps_its_mean() {
    // Half the view sees the background, half a light quad in front of the camera.
    let mut scene = constant(Vec3::splat(0.2));
    scene.materials.push(wavetrace::scene::NamedMaterial {
        name: "light".into(),
        material: wavetrace::scene::Material::Emissive { radiance: Vec3::splat(3.0) },
    });
    scene.quads.push(wavetrace::scene::Quad {
        corner: Vec3::new(0.0, -10.0, -1.0),
        u: Vec3::new(10.0, 0.0, 0.0),
        v: Vec3::new(0.0, 20.0, 0.0),
        material: 0,
    });
    let s = one_pixel(1 << 20);
    let films = films(&scene, &s);
    let cpu = films.iter().find(|(m, _)| *m == Method::Cpu).unwrap().1.pixel(0, 0).mean();
    assert!(cpu[0] > 1.0 && cpu[0] < 2.2, "the pixel straddles the edge: {cpu:?}");
    for (method, film) in &films {
        let m = film.pixel(0, 0).mean();
        assert!((m[0] / cpu[0] - 1.0).abs() <= 1e-5, "{}: mean {m:?} vs cpu {cpu:?}", method.name());
        if method.needs_gpu() {
            let again =
                render(*method, &scene, &s, &MethodOptions::default(), common::gpu(), &|_| {}).unwrap();
            assert_eq!(&again.film, film, "{}: repeat renders are bit-identical", method.name());
        }
    }
}

/// The compensated film is 64 bytes a pixel (32 before): a 1920×1080 film, the largest the
/// shipped configs render, still fits one storage binding of the software driver (128 MiB).
#[test]
fn a_1080p_film_fits_one_storage_binding_of_the_software_driver() {
    let bytes = 1920 * 1080 * std::mem::size_of::<wavetrace::layout::FilmPixel>();
    assert_eq!(std::mem::size_of::<wavetrace::layout::FilmPixel>(), 64);
    assert!(bytes <= 128 << 20, "{bytes} bytes");
}
