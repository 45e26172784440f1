//! The render space's plumbing (issue 28, `--render-space`; its numerics are tested in
//! stability.rs): textures stay on their surfaces in camera space, and configs and the CLI
//! record the knob and refuse bad values with a clear error. (Written on the issue-28 helper's
//! branch, adapted to main.)

use crate::common;

use std::path::Path;
use wavetrace::experiment::config::ExperimentConfig;
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::numerics::{NumericOptions, RayOffset};
use wavetrace::render_space::RenderSpace;
use wavetrace::scene::stress::StressTransform;
use wavetrace::scene::{builtin, Scene};
use wavetrace::settings::{Accel, RenderSettings};
use wavetrace::stats::z_test;

/// Small enough for the software driver: the methods trace the same paths as the reference
/// (same seed), so a few samples suffice to tell rounding from a different scene.
fn settings() -> RenderSettings {
    RenderSettings {
        width: 40,
        height: 24,
        spp: 4,
        max_depth: 50,
        seed: 5,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

fn try_run(method: Method, scene: &Scene, o: &MethodOptions) -> anyhow::Result<RenderOutput> {
    let gpu = if method.needs_gpu() { common::gpu() } else { None };
    render(method, scene, &settings(), o, gpu, &|_| {})
}

fn robust(translate: [f64; 3], render_space: RenderSpace) -> MethodOptions {
    MethodOptions {
        numerics: NumericOptions { ray_offset: RayOffset::Robust, render_space, ..Default::default() },
        stress: StressTransform { translate, ..Default::default() },
        ..Default::default()
    }
}

/// stability.rs's test: ≥ 99% of pixels pass the z-test at α = 0.01 against the untransformed
/// scene, image means within 1%, and no self-hit (primary or shadow).
fn holds(out: &RenderOutput, reference: &RenderOutput) -> (bool, String) {
    let t = z_test(&out.film, &reference.film, 0.01);
    let f = &out.failures;
    let ok = t.pass_fraction >= 0.99 && t.mean_rel_diff <= 0.01 && f.self_hits + f.shadow_self_hits == 0;
    (ok, format!("{:.4} of pixels pass, means differ by {:.2e}, {f:?}", t.pass_fraction, t.mean_rel_diff))
}

/// Textures are looked up in the scene's own space, which the render space must not move:
/// a checker and a marble far away in camera space look as they do at the origin.
#[test]
fn textures_stay_on_their_surfaces_in_camera_space() {
    use wavetrace::scene::{Material, Texture};
    let mut scene = builtin::by_name("three-spheres").unwrap();
    for m in &mut scene.materials {
        if let Material::Lambertian { albedo: Texture::Solid(c) } = m.material {
            m.material = Material::Lambertian {
                albedo: Texture::Checker { scale: 0.3, even: c, odd: glam::Vec3::new(0.9, 0.2, 0.1) },
            };
        }
    }
    let reference = try_run(Method::CpuF64, &scene, &robust([0.0; 3], RenderSpace::World)).unwrap();
    let far = robust([3e6, -2e6, 1e6], RenderSpace::Camera);
    let mut methods = vec![Method::Cpu];
    if common::gpu().is_some() {
        methods.push(Method::Megakernel);
    }
    for m in methods {
        let (ok, why) = holds(&try_run(m, &scene, &far).unwrap(), &reference);
        assert!(ok, "{}: textured scene in camera space: {why}", m.name());
    }
}

/// A bad render space in a config names the file, the field and the reason.
#[test]
fn a_bad_render_space_in_a_config_is_refused_with_file_field_and_reason() {
    let config = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres"],
        "resolutions": ["8x8"],
        "spp": [1],
        "methods": [{"method": "cpu", "render_space": ["world", "object"]}],
    });
    let path = Path::new("configs/far.json");
    let e = ExperimentConfig::from_str(&config.to_string(), path).expect_err("refused");
    assert_eq!(e.file, path.display().to_string());
    assert_eq!(e.path, "methods[0].render_space[1]", "{e}");
    assert!(e.reason.contains("unknown value \"object\"") && e.reason.contains("\"camera\""), "{e}");
    // A good sweep expands into one labelled variant per space, defaulting to camera.
    let ok = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres"],
        "resolutions": ["8x8"],
        "spp": [1],
        "methods": [{"method": "cpu", "render_space": ["world", "camera"]}, {"method": "cpu-f64"}],
    });
    let c = ExperimentConfig::from_str(&ok.to_string(), path).unwrap();
    let got: Vec<(String, RenderSpace)> =
        c.methods.iter().map(|v| (v.label.clone(), v.options.numerics.render_space)).collect();
    assert_eq!(got[0].1, RenderSpace::World);
    assert!(got[0].0.contains("render-space=world"), "{got:?}");
    assert_eq!(got[1].1, RenderSpace::Camera);
    assert_eq!(got[2].1, RenderSpace::Camera);
}

/// The CLI takes `--render-space`, refuses an unknown space, and writes the space it rendered
/// in into the EXR's attributes and the run record.
#[test]
fn the_cli_records_the_render_space_and_refuses_unknown_ones() {
    let dir = common::tmp().join("render-space-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let (exr, report) = (dir.join("far.exr"), dir.join("far.json"));
    let base = ["render", "--scene", "three-spheres", "--method", "cpu", "--width", "8", "--height", "6"];
    let out = std::process::Command::new(common::bin())
        .args(base)
        .args(["--spp", "1", "--translate", "1e7", "--render-space", "world", "--out"])
        .arg(&exr)
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("render space world"));
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["options"]["render_space"], "world");
    let (_, attrs) = wavetrace::image_io::read_exr(&exr).unwrap();
    assert!(attrs.iter().any(|(k, v)| k == "wavetrace.render_space" && v == "world"), "{attrs:?}");
    let bad = std::process::Command::new(common::bin())
        .args(base)
        .args(["--render-space", "object", "--out"])
        .arg(&exr)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(2), "{err}");
    assert!(err.contains("--render-space") && err.contains("camera"), "{err}");
}
