//! Where methods fail numerically (issue 12, README "Where methods fail — numerically"): the
//! stress transforms render the same image in exact arithmetic, so the robust settings must
//! pass the agreement z-test against the untransformed scene where the book's settings fail it
//! (the negative control); the knobs work alike on every method, repeat bit for bit, and a scene
//! whose f32 arithmetic overflows is refused rather than rendered wrong.

use crate::common;

use std::process::Command;
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
use wavetrace::render_space::RenderSpace;
use wavetrace::scene::stress::StressTransform;
use wavetrace::scene::{builtin, Background, Material, NamedMaterial, Scene, Sphere};
use wavetrace::settings::{Accel, RenderSettings};
use wavetrace::stats::z_test;

fn settings(spp: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 27,
        spp,
        max_depth: 50,
        seed: 3,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

fn try_run(
    method: Method,
    scene: &Scene,
    s: &RenderSettings,
    o: &MethodOptions,
) -> anyhow::Result<RenderOutput> {
    let gpu = if method.needs_gpu() { common::gpu() } else { None };
    render(method, scene, s, o, gpu, &|_| {})
}

fn run(method: Method, scene: &Scene, s: &RenderSettings, o: &MethodOptions) -> RenderOutput {
    try_run(method, scene, s, o).unwrap()
}

/// The knobs in world space, where the stress transform's scene is stored in f32 as moved (the
/// tests below measure the methods' arithmetic there; camera space has its own tests).
fn options(ray_offset: RayOffset, sphere_hit: SphereHit, stress: StressTransform) -> MethodOptions {
    in_space(RenderSpace::World, ray_offset, sphere_hit, stress)
}

fn in_space(
    space: RenderSpace,
    ray_offset: RayOffset,
    sphere_hit: SphereHit,
    stress: StressTransform,
) -> MethodOptions {
    MethodOptions {
        numerics: NumericOptions { ray_offset, sphere_hit, fresnel: Fresnel::Schlick, render_space: space },
        stress,
        ..Default::default()
    }
}

/// `methods`, and the GPU methods where there is a GPU.
fn with_gpu_methods(mut methods: Vec<Method>) -> Vec<Method> {
    if common::gpu().is_some() {
        methods.extend([Method::Megakernel, Method::Wavefront]);
    }
    methods
}

fn scale(s: f64) -> StressTransform {
    StressTransform { scale: s, ..Default::default() }
}

fn translate(d: f64) -> StressTransform {
    StressTransform { translate: [d; 3], ..Default::default() }
}

/// The stress points of the issue: scale 1e-3 and 1e4, distance 1e5 (along the diagonal).
fn stress_points() -> [(&'static str, StressTransform); 3] {
    [("scale 1e-3", scale(1e-3)), ("scale 1e4", scale(1e4)), ("translate 1e5", translate(1e5))]
}

/// Whether `out` passes the agreement bar against `reference` (`common::assert_agree_rays`'s:
/// ≥ 99% of pixels pass the z-test, image means within 1%).
fn agrees(out: &RenderOutput, reference: &RenderOutput) -> (bool, String) {
    let t = z_test(&out.film, &reference.film, 0.01);
    let ok = t.pass_fraction >= 0.99 && t.mean_rel_diff <= 0.01;
    (ok, format!("{:.4} of pixels pass, means differ by {:.2e}", t.pass_fraction, t.mean_rel_diff))
}

#[test]
fn robust_offsets_and_the_stable_sphere_hit_hold_under_stress_on_every_method() {
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(16);
    let reference = run(Method::CpuF64, &scene, &s, &MethodOptions::default());
    let methods = with_gpu_methods(vec![Method::Cpu, Method::CpuF64]);
    for (name, stress) in stress_points() {
        for &m in &methods {
            let out = run(m, &scene, &s, &options(RayOffset::Robust, SphereHit::Stable, stress));
            let (ok, why) = agrees(&out, &reference);
            eprintln!("{} robust+stable at {name}: {why}, {:?}", m.name(), out.failures);
            assert!(ok, "{} robust+stable at {name} disagrees with the untransformed scene: {why}", m.name());
            assert_eq!(out.failures.self_hits + out.failures.shadow_self_hits, 0, "{} at {name}", m.name());
        }
    }
}

/// The negative control: the book's t_min and quadratic fail the same test (at scale 1e-3 the
/// spheres' radius, 5e-4, is below t_min and rays pass through them; at 1e4 t_min is below the
/// hit points' rounding error and rays hit the surface they leave).
#[test]
fn the_books_settings_fail_the_same_test() {
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(16);
    let reference = run(Method::CpuF64, &scene, &s, &MethodOptions::default());
    for (name, stress) in [("scale 1e-3", scale(1e-3)), ("scale 1e4", scale(1e4))] {
        let out = run(Method::Cpu, &scene, &s, &options(RayOffset::default(), SphereHit::Book, stress));
        let (ok, why) = agrees(&out, &reference);
        eprintln!("cpu tmin+book at {name}: {why}, {:?}", out.failures);
        assert!(!ok, "the book's settings passed at {name}: the test cannot tell ({why})");
    }
    // At 1e4 the failure is self-hits, and the counters see them.
    let out = run(Method::Cpu, &scene, &s, &options(RayOffset::default(), SphereHit::Book, scale(1e4)));
    assert!(out.failures.self_hits > 1000, "{:?}", out.failures);
}

#[test]
fn failure_counters_agree_across_methods() {
    let Some(_) = common::gpu() else { return };
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(8);
    let o = options(RayOffset::default(), SphereHit::Stable, scale(100.0));
    let cpu = run(Method::Cpu, &scene, &s, &o).failures;
    assert!(cpu.self_hits > 10_000 && cpu.depth_cut > 100, "{cpu:?}");
    for m in [Method::Megakernel, Method::Wavefront] {
        let gpu = run(m, &scene, &s, &o).failures;
        eprintln!("{}: {gpu:?} against cpu {cpu:?}", m.name());
        // The same paths, up to the few that rounding sends another way.
        let close = |a: u64, b: u64| (a as f64 - b as f64).abs() <= 0.02 * b as f64;
        assert!(close(gpu.self_hits, cpu.self_hits) && close(gpu.depth_cut, cpu.depth_cut), "{}", m.name());
    }
}

#[test]
fn every_knob_repeats_bit_identically() {
    let mut scene = builtin::by_name("cornell").unwrap();
    // Glass in the box, so the Fresnel knob is exercised.
    scene.materials.push(NamedMaterial { name: "glass".into(), material: Material::Dielectric { ior: 1.5 } });
    let glass = scene.materials.len() as u32 - 1;
    scene.spheres.push(Sphere { center: glam::Vec3::new(190.0, 90.0, 190.0), radius: 90.0, material: glass });
    let s = RenderSettings { nee: true, ..settings(4) };
    let o = MethodOptions {
        numerics: NumericOptions {
            ray_offset: RayOffset::Robust,
            sphere_hit: SphereHit::Book,
            fresnel: Fresnel::Exact,
            render_space: RenderSpace::World,
        },
        stress: StressTransform { scale: 1e-2, translate: [3.0, -2.0, 1e3] },
        ..Default::default()
    };
    let methods = with_gpu_methods(vec![Method::Cpu, Method::CpuF64]);
    for m in methods {
        let (a, b) = (run(m, &scene, &s, &o), run(m, &scene, &s, &o));
        assert_eq!(a.film, b.film, "{}", m.name());
        assert_eq!(a.failures, b.failures, "{}", m.name());
    }
}

#[test]
fn exact_fresnel_agrees_across_methods() {
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(32);
    let o = MethodOptions {
        numerics: NumericOptions { fresnel: Fresnel::Exact, ..Default::default() },
        ..Default::default()
    };
    let reference = run(Method::CpuF64, &scene, &s, &o);
    let methods = with_gpu_methods(vec![Method::Cpu]);
    for m in methods {
        let (ok, why) = agrees(&run(m, &scene, &s, &o), &reference);
        assert!(ok, "{} with exact Fresnel: {why}", m.name());
    }
}

/// Camera space (issue 28): the scene moved in f64 so that the camera is at the origin before it
/// is stored in f32. Far from the origin, along the diagonal and off it, every method with the
/// robust settings agrees with the untransformed scene and no ray hits the surface it leaves.
#[test]
fn camera_space_holds_far_from_the_origin_on_every_method() {
    let s = settings(16);
    let far = [[1e6; 3], [1e7; 3], [3e6, -2e6, 1e6]];
    let methods = with_gpu_methods(vec![Method::Cpu, Method::CpuF64]);
    for name in ["three-spheres", "cornell"] {
        let scene = builtin::by_name(name).unwrap();
        let reference = run(Method::CpuF64, &scene, &s, &MethodOptions::default());
        for translate in far {
            let stress = StressTransform { translate, ..Default::default() };
            for &m in &methods {
                let o = in_space(RenderSpace::Camera, RayOffset::Robust, SphereHit::Stable, stress);
                let out = run(m, &scene, &s, &o);
                let (ok, why) = agrees(&out, &reference);
                eprintln!("{name} {} camera at {translate:?}: {why}, {:?}", m.name(), out.failures);
                assert!(ok, "{name} {} in camera space at {translate:?}: {why}", m.name());
                let f = out.failures;
                assert_eq!(f.self_hits + f.shadow_self_hits, 0, "{name} {} at {translate:?}", m.name());
            }
        }
    }
}

/// The negative control: the same test in world space fails for the f32 methods at 1e7 (the f32
/// spacing there, 1.0, is the size of three-spheres' spheres; at 1e6, spaced 0.0625, it still
/// passes this bar), so the test above can tell.
#[test]
fn world_space_fails_the_same_test_far_from_the_origin() {
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = settings(16);
    let reference = run(Method::CpuF64, &scene, &s, &MethodOptions::default());
    let stress = StressTransform { translate: [1e7; 3], ..Default::default() };
    for m in with_gpu_methods(vec![Method::Cpu]) {
        let out =
            run(m, &scene, &s, &in_space(RenderSpace::World, RayOffset::Robust, SphereHit::Stable, stress));
        let (ok, why) = agrees(&out, &reference);
        eprintln!("{} world at 1e7: {why}, {:?}", m.name(), out.failures);
        assert!(!ok, "{} in world space at 1e7 passed: the test cannot tell ({why})", m.name());
    }
}

/// Near the origin the two spaces render the same image up to rounding, on every method.
#[test]
fn camera_and_world_space_agree_near_the_origin() {
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = settings(8);
    for m in with_gpu_methods(vec![Method::Cpu]) {
        let o = |space| in_space(space, RayOffset::Robust, SphereHit::Stable, StressTransform::default());
        let world = run(m, &scene, &s, &o(RenderSpace::World));
        let camera = run(m, &scene, &s, &o(RenderSpace::Camera));
        assert_ne!(world.film, camera.film, "{}: moved, so rounded differently", m.name());
        let (ok, why) = agrees(&camera, &world);
        assert!(ok, "{}: {why}", m.name());
    }
}

/// The f32-range refusal looks at the space that is rendered: a scene 2e19 from the origin
/// (coordinates whose squares overflow f32) is refused in world space and rendered in camera
/// space, where its coordinates are small. (In f64, where the host moves it, 2e19 is spaced 4096
/// apart: the move keeps what f64 kept of the scene, no more.)
#[test]
fn the_range_refusal_looks_at_the_rendered_space() {
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = RenderSettings { width: 8, height: 8, spp: 1, ..settings(1) };
    let stress = StressTransform { translate: [2e19; 3], ..Default::default() };
    for m in with_gpu_methods(vec![Method::Cpu]) {
        let world = in_space(RenderSpace::World, RayOffset::Robust, SphereHit::Stable, stress);
        let e = try_run(m, &scene, &s, &world).expect_err("refused in world space").to_string();
        assert!(e.contains("overflows f32"), "{}: {e}", m.name());
        let camera = in_space(RenderSpace::Camera, RayOffset::Robust, SphereHit::Stable, stress);
        try_run(m, &scene, &s, &camera).unwrap_or_else(|e| panic!("{}: camera space refused: {e}", m.name()));
    }
}

/// A sphere of radius 1e38 around the camera: r² overflows f32, so an f32 method would see no
/// hit and render open sky (with no NaN to warn). The f32 methods refuse it, naming the limit;
/// `cpu-f64` renders the emitter it is.
#[test]
fn a_scene_that_overflows_f32_is_refused_not_rendered_as_sky() {
    let mut scene = builtin::by_name("three-spheres").unwrap();
    scene.background = Background::Sky;
    scene.materials.push(NamedMaterial {
        name: "huge light".into(),
        material: Material::Emissive { radiance: glam::Vec3::splat(0.5) },
    });
    scene.spheres =
        vec![Sphere { center: glam::Vec3::ZERO, radius: 1e38, material: scene.materials.len() as u32 - 1 }];
    let s = RenderSettings { width: 8, height: 8, spp: 2, ..settings(2) };
    let methods = with_gpu_methods(vec![Method::Cpu]);
    for m in methods {
        let e = try_run(m, &scene, &s, &MethodOptions::default()).expect_err("refused").to_string();
        assert!(e.contains("overflows f32") && e.contains("3.403e38"), "{}: {e}", m.name());
    }
    let truth = run(Method::CpuF64, &scene, &s, &MethodOptions::default());
    for p in &truth.film.pixels {
        assert_eq!(p.mean(), [0.5; 3], "the camera is inside the light");
    }
    // No --scale brings it into f32's range: radius and camera are 1e37 apart, and either the
    // radius squared overflows or the camera's pixel spacing squared underflows.
    for k in [1e-10, 1e-20, 1e-30] {
        let o = MethodOptions { stress: scale(k), ..Default::default() };
        let e = try_run(Method::Cpu, &scene, &s, &o).expect_err("refused").to_string();
        assert!(e.contains("overflows f32") || e.contains("underflows f32"), "scale {k}: {e}");
    }
}

#[test]
fn bad_numeric_arguments_are_refused_with_a_message() {
    for (flag, value, says) in [
        ("--scale", "0", "scale must be a finite number > 0"),
        ("--scale", "-1", "scale must be a finite number > 0"),
        ("--scale", "NaN", "scale must be a finite number > 0"),
        ("--translate", "1e39,0,0", "overflows f32"),
        ("--translate", "1,2", "expected X,Y,Z"),
        ("--ray-offset", "tmin=-1", "tmin must be a finite distance"),
        ("--ray-offset", "epsilon", "expected \"tmin\""),
    ] {
        let out = Command::new(crate::common::bin())
            .args(["render", "--scene", "three-spheres", "--method", "cpu", "--out", "/nonexistent/x.exr"])
            // `--scale=-1`: a bare -1 would read as a flag.
            .arg(format!("{flag}={value}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(err.contains(says), "{flag} {value}: {err}");
    }
}
