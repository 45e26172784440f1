//! Scale: the `spheres-N` family up to a million spheres. The layout is what its doc says (N
//! spheres, deterministic, no overlaps), scenes too big for the adapter are refused naming the
//! buffer, and a million spheres render alike on the CPU and both GPU methods. Small images:
//! these run on the software driver.

use crate::common;

use std::collections::HashMap;
use wavetrace::bvh;
use wavetrace::film::Film;
use wavetrace::gpu::buffers::human_bytes;
use wavetrace::gpu::scene_buffers::{binding_needed, buffer_sizes, check_fits, check_fits_limits};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::packed_scene::PackedScene;
use wavetrace::scene::{builtin, Scene};
use wavetrace::settings::{Accel, RenderSettings};
use wavetrace::stats::z_test;

const MILLION: &str = "spheres-1000000";

/// Built once per test binary: a million-sphere build takes about a second.
fn million() -> &'static Scene {
    static SCENE: std::sync::OnceLock<Scene> = std::sync::OnceLock::new();
    SCENE.get_or_init(|| builtin::by_name(MILLION).unwrap())
}

/// No two small spheres overlap: each is compared with those in its own and neighbouring cells
/// of a hash grid whose cells are as wide as the largest diameter (O(N), not O(N²)).
fn assert_no_overlaps(scene: &Scene) {
    let small = &scene.spheres[1..];
    let cell = 2.0 * small.iter().map(|s| s.radius).fold(0.0, f32::max);
    let key = |x: f32, z: f32| ((x / cell).floor() as i64, (z / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, s) in small.iter().enumerate() {
        grid.entry(key(s.center.x, s.center.z)).or_default().push(i);
    }
    for (i, s) in small.iter().enumerate() {
        let (kx, kz) = key(s.center.x, s.center.z);
        for dx in -1..=1 {
            for dz in -1..=1 {
                for &j in grid.get(&(kx + dx, kz + dz)).map_or(&[][..], |v| v.as_slice()) {
                    let t = &small[j];
                    assert!(
                        j == i || s.center.distance(t.center) > s.radius + t.radius,
                        "{}: small spheres {i} and {j} overlap",
                        scene.name
                    );
                }
            }
        }
    }
}

#[test]
fn spheres_n_is_n_small_spheres_on_the_ground_without_overlaps() {
    let a = builtin::by_name("spheres-5000").unwrap();
    assert_eq!(a.name, "spheres-5000");
    assert_eq!(a.spheres.len(), 5000 + 1);
    assert_eq!(a.spheres[0].radius, 1000.0, "the book's ground first");
    assert!(a.spheres[1..].iter().all(|s| s.radius < 1.0));
    assert_eq!(builtin::by_name("spheres-5000").unwrap(), a, "two builds are identical");
    assert_no_overlaps(&a);
    // The book's three material kinds, mostly diffuse.
    let kinds = |k| a.spheres[1..].iter().filter(|s| a.material(s).kind_name() == k).count() as f64;
    assert!((kinds("lambertian") / 5000.0 - 0.80).abs() < 0.03);
    assert!((kinds("metal") / 5000.0 - 0.15).abs() < 0.03);
    assert!((kinds("dielectric") / 5000.0 - 0.05).abs() < 0.02);

    let m = million();
    assert_eq!(m.spheres.len(), 1_000_000 + 1);
    assert_no_overlaps(m);
    assert!(builtin::by_name("spheres-0").is_none());
    assert!(builtin::by_name("spheres-1000001").is_none());
}

#[test]
fn the_camera_frames_the_whole_grid() {
    // Every small sphere's centre projects inside a 16:9 frame, at small and large N.
    for scene in
        [&builtin::by_name("spheres-7").unwrap(), &builtin::by_name("spheres-5000").unwrap(), million()]
    {
        let c = &scene.camera;
        let w = (c.lookfrom - c.lookat).normalize();
        let u = c.vup.cross(w).normalize();
        let v = w.cross(u);
        let half_h = (c.vfov.to_radians() / 2.0).tan();
        let half_w = half_h * 16.0 / 9.0;
        for s in &scene.spheres[1..] {
            let d = s.center - c.lookfrom;
            let depth = -d.dot(w);
            assert!(depth > 0.0);
            let (x, y) = (d.dot(u) / depth, d.dot(v) / depth);
            assert!(x.abs() < half_w && y.abs() < half_h, "{}: a sphere is out of frame", scene.name);
        }
    }
}

#[test]
fn a_million_spheres_fit_lavapipe_and_the_loop_limit() {
    let packed = PackedScene::new(million(), Accel::Bvh);
    // lavapipe's limits (DESIGN.md §5): 128 MiB per storage binding.
    check_fits_limits(&packed, "llvmpipe", 128 << 20, 1 << 31).unwrap();
    // loop_limit::check_loop_limit's bound at the book's depth 50 stays under llvmpipe's 65535
    // loop iterations per invocation: leaves stay small however many spheres there are.
    let worst = 50 * (packed.largest_leaf() as u64 + bvh::MAX_DEPTH as u64);
    eprintln!("largest leaf {}, worst case {worst} iterations", packed.largest_leaf());
    assert!(worst <= 65_535, "worst case {worst}");
    if let Some(ctx) = common::gpu() {
        check_fits(&packed, &ctx.summary).unwrap();
    }
}

#[test]
fn scenes_too_big_for_the_adapter_are_refused_naming_the_buffer() {
    let packed = PackedScene::new(&builtin::by_name("spheres-20000").unwrap(), Accel::Bvh);
    let sizes = buffer_sizes(&packed);
    // The per-binding limit each buffer needs (the primitives and nodes split over up to four).
    let needs: Vec<(&str, u64, u64)> = sizes.iter().map(|&(l, b)| (l, b, binding_needed(l, b))).collect();
    let (label, size, biggest) = needs.iter().copied().max_by_key(|&(_, _, n)| n).unwrap();
    // One byte short for the neediest buffer, by either limit.
    for (binding, buffer) in [(biggest - 1, u64::MAX), (u64::MAX, biggest - 1)] {
        let err = check_fits_limits(&packed, "Tiny GPU", binding, buffer).unwrap_err().to_string();
        eprintln!("{err}");
        for want in [label, "Tiny GPU", &human_bytes(size), &human_bytes(biggest - 1), "20001 primitives"] {
            assert!(err.contains(want), "{want:?} missing from: {err}");
        }
    }
    check_fits_limits(&packed, "Tiny GPU", biggest, biggest).unwrap();
    // Each buffer is named when it alone is too big.
    for &(label, _, need) in &needs {
        let others = needs.iter().filter(|&&(l, _, _)| l != label).map(|&(_, _, n)| n).max().unwrap();
        if need > others {
            let err = check_fits_limits(&packed, "g", others, others).unwrap_err().to_string();
            assert!(err.contains(&format!("its {label} buffer")), "{err}");
        }
    }
}

fn settings() -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 18,
        spp: 4,
        max_depth: 50,
        seed: 1,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

fn run(method: Method) -> Film {
    let gpu = if method.needs_gpu() { common::gpu() } else { None };
    let out = render(method, million(), &settings(), &MethodOptions::default(), gpu, &|_| {}).unwrap();
    let film = out.film;
    let mean = film.image_mean();
    eprintln!("{MILLION} {method:?}: {:.3} s, image mean {mean:.4}", out.wall_seconds);
    // Sky above, a lit grey ground and the grid below: neither black nor blown out.
    assert!((0.2..1.2).contains(&mean), "{method:?}: image mean {mean}");
    assert_eq!(film.invalid_samples(), 0, "{method:?}");
    film
}

/// The agreement bar of tests/agreement.rs: ≥ 99% of pixels pass the z-test at α = 0.01, image
/// means within 1%, and (the same paths traced) ray counts within `ray_tolerance`.
fn assert_agree(name: &str, a: &Film, b: &Film, ray_tolerance: f64) {
    let t = z_test(a, b, 0.01);
    let (ra, rb) = (a.rays() as f64, b.rays() as f64);
    eprintln!(
        "{name}: {:.4} of pixels pass, means differ by {:.2e}, {ra} vs {rb} rays",
        t.pass_fraction, t.mean_rel_diff
    );
    assert!(t.pass_fraction >= 0.99, "{name}: only {:.4} of pixels pass ({t:?})", t.pass_fraction);
    assert!(t.mean_rel_diff <= 0.01, "{name}: image means differ by {:.4}", t.mean_rel_diff);
    assert!((ra - rb).abs() <= ray_tolerance * rb, "{name}: {ra} vs {rb} rays traced");
}

#[test]
fn a_million_spheres_render_alike_with_every_method() {
    let cpu = run(Method::Cpu);
    // f32 against f64 rounds differently at every bounce, so more paths part ways (agreement.rs).
    assert_agree("cpu vs cpu-f64", &cpu, &run(Method::CpuF64), 1e-2);
    if common::gpu().is_none() {
        return;
    }
    assert_agree("cpu vs megakernel", &cpu, &run(Method::Megakernel), common::F32_RAY_TOLERANCE);
    assert_agree("cpu vs wavefront", &cpu, &run(Method::Wavefront), common::F32_RAY_TOLERANCE);
}
