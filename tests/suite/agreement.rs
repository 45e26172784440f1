//! CPU reference vs megakernel: per-pixel z-tests and image means (DESIGN.md §4), the analytic
//! furnace, and bit-identical repeat renders. Small images: these run on the software driver.

use crate::common;

use wavetrace::camera::CameraFrame;
use wavetrace::film::Film;
use wavetrace::gpu::wavefront::{ShadePasses, WavefrontOptions};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::{builtin, Material, Scene, Texture};
use wavetrace::settings::{Accel, RenderSettings};

pub(crate) fn settings(width: u32, height: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        spp,
        max_depth: 50,
        seed: 1,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

pub(crate) fn run(method: Method, scene: &Scene, s: &RenderSettings) -> Film {
    let gpu = if method.needs_gpu() { common::gpu() } else { None };
    render(method, scene, s, &MethodOptions::default(), gpu, &|_| {}).unwrap().film
}

/// The issue's bar: ≥ 99% of pixels pass a z-test at α = 0.01, image means within 1%. The
/// methods trace the same paths, so their ray counts (rays/s in reports) agree too, up to the
/// paths that rounding sends another way: rare between f32 methods (`common::F32_RAY_TOLERANCE`), more between f32 and
/// f64, where a path's rounding differs at every bounce (0.43% measured on three-spheres: 1%).
fn assert_agree(name: &str, a: &Film, b: &Film) {
    common::assert_agree_rays(name, a, b, common::F32_RAY_TOLERANCE);
}

#[test]
fn cpu_and_megakernel_agree_on_three_spheres() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(96, 54, 64);
    assert_agree("three-spheres", &run(Method::Cpu, &scene, &s), &run(Method::Megakernel, &scene, &s));
}

#[test]
fn cpu_and_megakernel_agree_on_rtiow_final() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(96, 54, 32);
    assert_agree("rtiow-final", &run(Method::Cpu, &scene, &s), &run(Method::Megakernel, &scene, &s));
}

/// three-spheres with every texture kind: a checker ground, a marble (7 octaves) diffuse sphere
/// and a noise-tinted fuzzy metal.
pub(crate) fn textured_three_spheres() -> Scene {
    let mut scene = builtin::by_name("three-spheres").unwrap();
    for m in &mut scene.materials {
        m.material = match m.material {
            Material::Lambertian { albedo: Texture::Solid(c) } if c == glam::Vec3::splat(0.5) => {
                Material::Lambertian {
                    albedo: Texture::Checker {
                        scale: 0.5,
                        even: glam::Vec3::new(0.2, 0.3, 0.1),
                        odd: glam::Vec3::splat(0.9),
                    },
                }
            }
            Material::Lambertian { .. } => {
                Material::Lambertian { albedo: Texture::marble(4.0, 7, glam::Vec3::ONE) }
            }
            Material::Metal { .. } => {
                Material::Metal { albedo: Texture::noise(3.0, 4, glam::Vec3::splat(0.9)), fuzz: 0.2 }
            }
            ref other => other.clone(),
        };
    }
    scene
}

#[test]
fn textures_agree_on_cpu_megakernel_and_wavefront() {
    let scene = textured_three_spheres();
    let s = settings(96, 54, 32);
    let cpu = run(Method::Cpu, &scene, &s);
    // The textures are really there: the image differs from the untextured scene's.
    let plain = run(Method::Cpu, &builtin::by_name("three-spheres").unwrap(), &s);
    assert!((cpu.image_mean() - plain.image_mean()).abs() > 0.01, "textures change the image");
    common::assert_agree_rays("textures f32 vs f64", &cpu, &run(Method::CpuF64, &scene, &s), 1e-2);
    if common::gpu().is_none() {
        return;
    }
    assert_agree("textures cpu vs megakernel", &cpu, &run(Method::Megakernel, &scene, &s));
    assert_agree("textures cpu vs wavefront", &cpu, &run(Method::Wavefront, &scene, &s));
}

/// The costly-shading scene: every method renders the same image.
#[test]
fn rtiow_heavy_agrees_on_cpu_megakernel_and_wavefront() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("rtiow-heavy").unwrap();
    let s = settings(96, 54, 16);
    let cpu = run(Method::Cpu, &scene, &s);
    assert_agree("rtiow-heavy cpu vs megakernel", &cpu, &run(Method::Megakernel, &scene, &s));
    assert_agree("rtiow-heavy cpu vs wavefront", &cpu, &run(Method::Wavefront, &scene, &s));
}

/// The shading-divergence family: every costly pattern at once renders the same image on the
/// CPU, the megakernel and the wavefront with a shade pass per pattern (`--shade per-texture`)
/// and per material kind.
#[test]
fn rtiow_kinds_agrees_on_cpu_megakernel_and_wavefront() {
    let scene = builtin::by_name("rtiow-kinds-8").unwrap();
    let s = settings(96, 54, 16);
    let cpu = run(Method::Cpu, &scene, &s);
    common::assert_agree_rays("rtiow-kinds-8 f32 vs f64", &cpu, &run(Method::CpuF64, &scene, &s), 1e-2);
    if common::gpu().is_none() {
        return;
    }
    assert_agree("rtiow-kinds-8 cpu vs megakernel", &cpu, &run(Method::Megakernel, &scene, &s));
    assert_agree("rtiow-kinds-8 cpu vs wavefront", &cpu, &run(Method::Wavefront, &scene, &s));
    let per_texture = MethodOptions {
        wavefront: WavefrontOptions { shade: ShadePasses::PerTexture, ..Default::default() },
        ..Default::default()
    };
    let wf = render(Method::Wavefront, &scene, &s, &per_texture, common::gpu(), &|_| {}).unwrap().film;
    assert_agree("rtiow-kinds-8 cpu vs wavefront per-texture", &cpu, &wf);
}

/// The scene-size family: a generated terrain of triangles renders the same image on every
/// method (its export and load: tests/suite/scene_format.rs, every built-in).
#[test]
fn a_generated_terrain_agrees_on_every_method() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("triangles-5000").unwrap();
    assert_eq!(scene.primitive_count(), 5000 + 3);
    let s = settings(96, 54, 16);
    let cpu = run(Method::Cpu, &scene, &s);
    assert_agree("triangles cpu vs megakernel", &cpu, &run(Method::Megakernel, &scene, &s));
    assert_agree("triangles cpu vs wavefront", &cpu, &run(Method::Wavefront, &scene, &s));
}

#[test]
fn cpu_f32_agrees_with_the_f64_ground_truth() {
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(64, 36, 32);
    common::assert_agree_rays(
        "f32 vs f64",
        &run(Method::Cpu, &scene, &s),
        &run(Method::CpuF64, &scene, &s),
        1e-2,
    );
}

#[test]
fn linear_loop_and_bvh_agree_on_the_gpu() {
    if common::gpu().is_none() {
        return;
    }
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(48, 27, 16);
    let linear = RenderSettings { accel: Accel::None, ..s.clone() };
    assert_agree(
        "bvh vs none",
        &run(Method::Megakernel, &scene, &s),
        &run(Method::Megakernel, &scene, &linear),
    );
}

#[test]
fn megakernel_repeats_bit_identically() {
    let Some(ctx) = common::gpu() else { return };
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(40, 24, 8);
    // Several dispatches per render, so accumulation across dispatches is exercised too.
    let mut opts = MethodOptions::default();
    opts.megakernel.samples_per_dispatch = 40 * 24 * 3;
    let a = render(Method::Megakernel, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
    let b = render(Method::Megakernel, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
    assert!(a.dispatches >= 3);
    assert_eq!(a.film, b.film);
}

/// Fraction of pixel (x, y) covered by the furnace sphere, from 16×16 pinhole rays in f64.
fn coverage(scene: &Scene, s: &RenderSettings, x: u32, y: u32) -> f64 {
    let f = CameraFrame::new(&scene.camera, s.width, s.height);
    let sphere = &scene.spheres[0];
    let (c, r) = (sphere.center.as_dvec3(), sphere.radius as f64);
    let mut hits = 0;
    for j in 0..16 {
        for i in 0..16 {
            let (dx, dy) = ((i as f64 + 0.5) / 16.0 - 0.5, (j as f64 + 0.5) / 16.0 - 0.5);
            let p = f.pixel00 + (x as f64 + dx) * f.pixel_delta_u + (y as f64 + dy) * f.pixel_delta_v;
            let d = (p - f.center).normalize();
            let oc = f.center - c;
            let b = oc.dot(d);
            if b * b - (oc.length_squared() - r * r) >= 0.0 && b < 0.0 {
                hits += 1;
            }
        }
    }
    hits as f64 / 256.0
}

/// Albedo 0.5 under white light: one bounce off a convex sphere always escapes, so the exact
/// pixel value is 1 − (1 − 0.5) · coverage. A pixel wholly inside or outside the sphere is 0.5 or 1.0
/// on every sample (one f32 product, exact), so its mean must be exact up to the film's f32 sum
/// (1e-6); the image mean, whose edge pixels are random, within 0.005 (pbrt-v4 allows 0.025,
/// which an albedo 4% off passes). Panics naming the first pixel off.
fn check_furnace(method: Method) {
    check_furnace_scene(method, &builtin::by_name("furnace").unwrap(), 0.5);
}

/// [`check_furnace`] on `scene`, whose sphere is claimed to have albedo 0.5 (`truth` is what the
/// analytic image assumes).
fn check_furnace_scene(method: Method, scene: &Scene, truth: f64) {
    check_furnace_settings(method, scene, truth, &settings(48, 32, 16));
}

/// [`check_furnace_scene`] at settings `s`.
fn check_furnace_settings(method: Method, scene: &Scene, truth: f64, s: &RenderSettings) {
    let scene = scene.clone();
    let s = s.clone();
    let film = run(method, &scene, &s);
    let (mut want, mut got) = (0.0, 0.0);
    for y in 0..s.height {
        for x in 0..s.width {
            let cov = coverage(&scene, &s, x, y);
            let m = film.pixel(x, y).mean();
            let expected = 1.0 - (1.0 - truth) * cov;
            want += expected;
            got += m.iter().sum::<f64>() / 3.0;
            if cov == 0.0 || cov == 1.0 {
                for c in m {
                    assert!(
                        (c - expected).abs() <= 1e-6,
                        "{method:?} pixel ({x},{y}) = {c}, want {expected}"
                    );
                }
            }
        }
    }
    let n = (s.width * s.height) as f64;
    let (want, got) = (want / n, got / n);
    assert!((got - want).abs() <= 0.005, "{method:?}: furnace mean {got}, analytic {want}");
    assert!(want < 0.9, "the sphere covers a good part of the frame");
    assert_eq!(film.invalid_samples(), 0);
}

#[test]
fn furnace_matches_its_analytic_image_on_cpu() {
    check_furnace(Method::Cpu);
    check_furnace(Method::CpuF64);
}

/// The furnace with its sphere's albedo 1% off (0.495): the tightened bar must reject it, on the
/// CPU and the GPU alike (negative control; the old ±0.025 bar passed albedos 4% off).
#[test]
fn furnace_rejects_an_albedo_one_percent_off() {
    let mut scene = builtin::by_name("furnace").unwrap();
    let mut changed = 0;
    for m in &mut scene.materials {
        if let Material::Lambertian { albedo: Texture::Solid(c) } = &mut m.material {
            *c *= 0.99;
            changed += 1;
        }
    }
    assert_eq!(changed, 1, "the furnace has one diffuse material");
    let mut methods = vec![Method::Cpu];
    if common::gpu().is_some() {
        methods.push(Method::Megakernel);
    }
    for method in methods {
        let caught = std::panic::catch_unwind(|| check_furnace_scene(method, &scene, 0.5));
        assert!(caught.is_err(), "{method:?}: an albedo of 0.495 passed the furnace bar");
        // And the check is not failing for another reason: told the truth, it passes.
        check_furnace_scene(method, &scene, 0.495);
    }
}

/// Roulette keeps the furnace's answer, exactly: pbrt-v4's rule never ends a path before its
/// second hit, and the furnace's paths escape after their first, so every sample is unchanged
/// (the exact pixels stay exact) on every method.
#[test]
fn roulette_keeps_the_furnace() {
    let scene = builtin::by_name("furnace").unwrap();
    let s = RenderSettings { roulette: true, ..settings(48, 32, 16) };
    let mut methods = vec![Method::Cpu, Method::CpuF64];
    if common::gpu().is_some() {
        methods.extend([Method::Megakernel, Method::Wavefront]);
    }
    for method in methods {
        check_furnace_settings(method, &scene, 0.5, &s);
        let off = run(method, &scene, &RenderSettings { roulette: false, ..s.clone() });
        assert_eq!(run(method, &scene, &s), off, "{method:?}: the same samples");
    }
}

#[test]
fn furnace_matches_its_analytic_image_on_the_gpu() {
    if common::gpu().is_none() {
        return;
    }
    check_furnace(Method::Megakernel);
}

/// Samples that overflow to infinity are dropped and counted, identically on CPU and GPU, and
/// never reach the image.
#[test]
fn non_finite_samples_are_counted_and_dropped_on_cpu_and_gpu() {
    // Albedo 1e30 under a background of 1e10: one bounce gives 1e40 = +inf in f32, while the
    // background's own samples (and their squares, summed in the f32 film) stay finite.
    let json = r#"{
      "format": "wavetrace-scene/1",
      "camera": {"lookfrom":[0,0,4],"lookat":[0,0,0],"vup":[0,1,0],"vfov":40,"defocus_angle":0,"focus_dist":4},
      "background": {"type":"constant","color":[1e10,1e10,1e10]},
      "materials": {"hot": {"type":"lambertian","albedo":[1e30,1e30,1e30]}},
      "objects": [{"type":"sphere","center":[0,0,0],"radius":1,"material":"hot"}]
    }"#;
    let scene = wavetrace::scene::load::from_str(json, "<test>", "overflow").unwrap();
    let s = settings(24, 16, 4);
    let cpu = run(Method::Cpu, &scene, &s);
    assert!(cpu.invalid_samples() > 0);
    assert!(cpu.pixels.iter().all(|p| p.mean().iter().all(|c| c.is_finite())));
    if common::gpu().is_some() {
        let gpu = run(Method::Megakernel, &scene, &s);
        assert_eq!(gpu.invalid_samples(), cpu.invalid_samples());
        assert!(gpu.pixels.iter().all(|p| p.mean().iter().all(|c| c.is_finite())));
    }
}
