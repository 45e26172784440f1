//! Edge cases every method must render: any scene the CPU reference renders, the GPU methods
//! render too, with the same image, and no GPU validation error ever reaches the user. Each case
//! once broke or could break a buffer size, a queue or a loop bound: empty arrays bound as
//! storage, a scene without primitives or lights, one pixel, one sample, one bounce.

use crate::common;

use glam::Vec3;
use wavetrace::gpu::wavefront::Compaction;
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::{builtin, Background, Material, Mesh, MeshSource, NamedMaterial, Quad, Scene, Sphere};
use wavetrace::settings::{Accel, RenderSettings};

const METHODS: [Method; 4] = [Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront];

fn settings(width: u32, height: u32, spp: u32, max_depth: u32, nee: bool) -> RenderSettings {
    RenderSettings { width, height, spp, max_depth, seed: 7, accel: Accel::Bvh, nee, roulette: false }
}

/// A scene with the three-spheres camera and sky, and these shapes.
fn scene(name: &str, materials: Vec<(&str, Material)>) -> Scene {
    let base = builtin::by_name("three-spheres").unwrap();
    Scene {
        name: name.into(),
        camera: base.camera,
        background: Background::Sky,
        materials: materials
            .into_iter()
            .map(|(n, m)| NamedMaterial { name: n.into(), material: m })
            .collect(),
        spheres: vec![],
        quads: vec![],
        meshes: vec![],
        images: vec![],
    }
}

fn grey() -> Material {
    Material::Lambertian { albedo: Vec3::splat(0.5).into() }
}

fn light() -> Material {
    Material::Emissive { radiance: Vec3::splat(4.0) }
}

/// A quad facing the camera (which looks down -z from (13, 2, 3) towards the origin).
fn facing_quad(material: u32) -> Quad {
    Quad {
        corner: Vec3::new(-1.0, -1.0, 0.0),
        u: Vec3::new(0.0, 0.0, 2.0),
        v: Vec3::new(0.0, 2.0, 0.0),
        material,
    }
}

fn cases() -> Vec<(Scene, RenderSettings)> {
    let small = || settings(12, 8, 8, 8, false);
    let empty = scene("no-objects", vec![]);
    let mut no_prims_but_material = scene("unused-material", vec![("grey", grey())]);
    no_prims_but_material.background = Background::Constant(Vec3::new(0.2, 0.4, 0.8));
    let mut one_quad = scene("one-quad", vec![("grey", grey())]);
    one_quad.quads.push(facing_quad(0));
    let mut one_triangle = scene("one-triangle", vec![("grey", grey())]);
    one_triangle.meshes.push(Mesh {
        source: MeshSource::File("inline.obj".into()),
        triangles: vec![[Vec3::new(0.0, -1.0, -1.0), Vec3::new(0.0, -1.0, 1.0), Vec3::new(0.0, 1.5, 0.0)]],
        uvs: None,
        material: 0,
    });
    let mut only_emitters = scene("only-emitters", vec![("light", light())]);
    only_emitters.background = Background::Constant(Vec3::ZERO);
    only_emitters.spheres.push(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 });
    only_emitters.quads.push(facing_quad(0));
    let mut only_glass = scene("only-glass", vec![("glass", Material::Dielectric { ior: 1.5 })]);
    only_glass.spheres.push(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 });
    only_glass.spheres.push(Sphere { center: Vec3::new(0.0, 0.0, -2.5), radius: 0.7, material: 0 });
    let three = builtin::by_name("three-spheres").unwrap();
    vec![
        (empty.clone(), small()),
        (empty, settings(12, 8, 8, 8, true)),
        (no_prims_but_material, small()),
        (one_quad.clone(), small()),
        (one_quad, settings(12, 8, 8, 8, true)),
        (one_triangle, small()),
        (only_emitters.clone(), small()),
        (only_emitters, settings(12, 8, 8, 8, true)),
        (only_glass, small()),
        // No lights, next-event estimation asked for: it must turn itself off, not index an
        // empty light list.
        (three.clone(), settings(12, 8, 8, 8, true)),
        (three.clone(), settings(1, 1, 16, 50, false)),
        (three.clone(), settings(16, 9, 1, 50, false)),
        (three, settings(16, 9, 8, 1, false)),
    ]
}

/// Every method renders every case, without invalid samples, to the same image as `cpu` (they
/// trace the same paths): each pixel's mean within 1e-3 relative (plus 1e-5) of the CPU's, except
/// the rare pixel where rounding sends a path another way (at most 2% of pixels, and the image
/// mean within 1%).
#[test]
fn every_method_renders_every_edge_case() {
    let gpu = common::gpu();
    let mut wavefront_scan = MethodOptions::default();
    wavefront_scan.wavefront.compaction = Compaction::Scan;
    for (scene, s) in cases() {
        let reference =
            render(Method::Cpu, &scene, &s, &MethodOptions::default(), None, &|_| {}).unwrap().film;
        let mut runs: Vec<(String, Method, MethodOptions)> =
            METHODS.iter().map(|&m| (m.name().to_string(), m, MethodOptions::default())).collect();
        runs.push(("wavefront (scan)".into(), Method::Wavefront, wavefront_scan.clone()));
        for (name, method, opts) in runs {
            if method.needs_gpu() && gpu.is_none() {
                continue;
            }
            let what = format!(
                "{} {}x{} {} spp depth {} nee {} on {name}",
                scene.name, s.width, s.height, s.spp, s.max_depth, s.nee
            );
            let film =
                match render(method, &scene, &s, &opts, if method.needs_gpu() { gpu } else { None }, &|_| {})
                {
                    Ok(out) => out.film,
                    Err(e) => panic!("{what}: {e:#}"),
                };
            assert_eq!((film.width, film.height, film.spp), (s.width, s.height, s.spp), "{what}");
            assert_eq!(film.invalid_samples(), 0, "{what}: invalid samples");
            let (a, b) = (film.mean_rgb(), reference.mean_rgb());
            let off = a.iter().zip(&b).filter(|(x, y)| (**x - **y).abs() > 1e-3 * y.abs() + 1e-5).count();
            assert!(off * 50 <= a.len(), "{what}: {off} of {} channel means differ from cpu", a.len());
            let (ma, mb) = (film.image_mean(), reference.image_mean());
            assert!((ma - mb).abs() <= 0.01 * mb.abs() + 1e-6, "{what}: image mean {ma} vs cpu {mb}");
        }
    }
}

/// The scenes without primitives show exactly the background, on every method.
#[test]
fn a_scene_without_objects_shows_the_background() {
    let mut s = scene("constant", vec![]);
    s.background = Background::Constant(Vec3::new(0.25, 0.5, 1.0));
    let settings = settings(5, 4, 3, 4, true);
    for method in METHODS {
        if method.needs_gpu() && common::gpu().is_none() {
            continue;
        }
        let film =
            render(method, &s, &settings, &MethodOptions::default(), common::gpu(), &|_| {}).unwrap().film;
        for p in film.mean_rgb().chunks(3) {
            assert_eq!(p, [0.25, 0.5, 1.0], "{}", method.name());
        }
        assert_eq!(film.rays(), (5 * 4 * 3) as u64, "{}: one camera ray per sample", method.name());
    }
}
