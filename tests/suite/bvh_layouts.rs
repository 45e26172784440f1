//! `--bvh` (issue 59): every BVH layout is made from the same binary build and tested with the
//! same slab test on boxes that only grow, so every method finds the same closest hits and the
//! films are the same bit for bit whatever the layout, on the CPU and in every way the GPU
//! traces (both megakernels, the wavefront's waves and regenerate + tail), and the wide layout
//! by either collapse (`--collapse greedy|sah`).

use crate::common;

use wavetrace::bvh::collapse::Collapse;
use wavetrace::bvh::BvhLayout;
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::scene::Scene;
use wavetrace::settings::{Accel, RenderSettings};

const LAYOUTS: [BvhLayout; 3] = [BvhLayout::Binary, BvhLayout::AilaLaine, BvhLayout::Wide];

fn settings(nee: bool) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 16,
        spp: 2,
        max_depth: 50,
        seed: 9,
        accel: Accel::Bvh,
        nee,
        roulette: false,
    }
}

fn run(method: Method, scene: &Scene, s: &RenderSettings, opts: &MethodOptions) -> RenderOutput {
    render(method, scene, s, opts, common::gpu(), &|_| {}).unwrap()
}

/// Each layout's film equals the binary layout's, and the report records the layout.
fn assert_layouts_agree(method: Method, scene: &Scene, s: &RenderSettings, opts: &MethodOptions) {
    let binary = run(method, scene, s, opts);
    for layout in &LAYOUTS[1..] {
        let out = run(method, scene, s, &MethodOptions { bvh: *layout, ..opts.clone() });
        assert_eq!(out.resolved.bvh, *layout);
        assert_eq!(out.film, binary.film, "{}: {method:?} {layout:?} {opts:?}", scene.name);
    }
    // The wide layout by the other collapse: the same leaves, found in another tree.
    let collapse = if Collapse::default() == Collapse::Sah { Collapse::Greedy } else { Collapse::Sah };
    let o = MethodOptions { bvh: BvhLayout::Wide, collapse, ..opts.clone() };
    assert_eq!(run(method, scene, s, &o).film, binary.film, "{}: {method:?} {collapse:?}", scene.name);
}

/// Spheres (rtiow-final, no NEE); quads and an emitter with NEE (Cornell); every shape and
/// material (mesh-room, NEE), on both CPU references and the megakernel, and mesh-room on the
/// wavefront's regenerate + tail too (the other ways share their traversal code with these).
#[test]
fn every_layout_gives_the_binary_layouts_film() {
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json");
    for (name, nee) in [("rtiow-final", false), ("cornell", true), (room, true)] {
        let scene = Scene::resolve(name).unwrap();
        for method in [Method::Cpu, Method::CpuF64] {
            assert_layouts_agree(method, &scene, &settings(nee), &MethodOptions::default());
        }
        if common::gpu().is_none() {
            continue;
        }
        // mesh-room (every shape, NEE's shadow rays) on the megakernel and regenerate + tail:
        // the regenerating megakernel runs the megakernel's traversal, and waves the same
        // intersect and shadow passes; the other scenes on the megakernel. (Each layout and way
        // compiles its own pipelines: most of this test's cost with a cold shader cache.)
        let ways = common::gpu_ways();
        let take: &[usize] = if name == room { &[0, 3] } else { &[0] };
        for (method, opts) in take.iter().map(|&i| ways[i].clone()) {
            assert_layouts_agree(method, &scene, &settings(nee), &opts);
        }
    }
}

/// The linear loop has one leaf and no layout to choose: `--accel none` with another layout is
/// refused, naming both flags.
#[test]
fn accel_none_takes_the_binary_layout_only() {
    let scene = Scene::resolve("three-spheres").unwrap();
    let s = RenderSettings { accel: Accel::None, ..settings(false) };
    let opts = MethodOptions { bvh: BvhLayout::Wide, ..Default::default() };
    let err = render(Method::Cpu, &scene, &s, &opts, None, &|_| {}).err().unwrap().to_string();
    assert!(err.contains("--accel none") && err.contains("--bvh wide"), "{err}");
}

/// Primitives and BVH nodes split over several storage bindings, as 10⁷ triangles need on
/// lavapipe's 128 MiB (`gpu/scene_split.rs`), give the one-binding film bit for bit: a device
/// posing as one whose bindings hold 64 KiB splits mesh-room's 216 KiB of primitives over four
/// and its nodes over two (wide) or three (binary, aila-laine), every shape and NEE included.
/// Each layout on the megakernel; the wavefront's regenerate + tail on the binary one.
#[test]
fn scenes_split_over_bindings_give_the_one_binding_film() {
    let Some(shared) = common::gpu() else { return };
    let mut posing = wavetrace::gpu::context::GpuContext::new(Some(&shared.summary.name)).unwrap();
    posing.summary.max_storage_buffer_binding_size = 64 << 10;
    let room =
        Scene::resolve(concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json")).unwrap();
    let s = settings(true);
    let ways = common::gpu_ways();
    let mut cases: Vec<_> =
        LAYOUTS.iter().map(|&bvh| (ways[0].0, MethodOptions { bvh, ..ways[0].1.clone() })).collect();
    // The wavefront's passes bind the split scene alike in both schedules: regenerate + tail.
    cases.push(ways[3].clone());
    for (method, opts) in cases {
        let split = render(method, &room, &s, &opts, Some(&posing), &|_| {}).unwrap();
        assert_eq!(split.film, run(method, &room, &s, &opts).film, "{method:?} {opts:?}");
    }
    // Past four bindings the scene is refused with the sizes, before any upload.
    posing.summary.max_storage_buffer_binding_size = 4 << 10;
    let err = render(Method::Megakernel, &room, &s, &MethodOptions::default(), Some(&posing), &|_| {})
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("primitives") && err.contains("at most 4"), "{err}");
}

/// A pipeline past the adapter's limits is refused before wgpu creates it, naming the limit,
/// the need and the knob: too few storage buffers per stage for the scene's 13 bindings plus
/// the pass's own, and too little workgroup memory for `--stack workgroup`'s short stacks
/// (8 entries × 2 arrays × 4 bytes × 64 threads = 4096 bytes) on a device posing as smaller.
#[test]
fn pipelines_past_the_adapters_limits_are_refused_before_creation() {
    let Some(shared) = common::gpu() else { return };
    let scene = Scene::resolve("three-spheres").unwrap();
    let s = RenderSettings { width: 16, height: 8, spp: 1, ..settings(false) };
    let mut posing = wavetrace::gpu::context::GpuContext::new(Some(&shared.summary.name)).unwrap();
    let refusal = |posing: &wavetrace::gpu::context::GpuContext, opts: &MethodOptions| {
        render(Method::Megakernel, &scene, &s, opts, Some(posing), &|_| {}).err().unwrap().to_string()
    };
    posing.summary.max_storage_buffers_per_shader_stage = 12;
    let err = refusal(&posing, &MethodOptions::default());
    assert!(err.contains("max_storage_buffers_per_shader_stage") && err.contains("allows 12"), "{err}");
    assert!(err.contains("storage buffers but") && !err.contains("Validation"), "{err}");
    posing.summary.max_storage_buffers_per_shader_stage = shared.summary.max_storage_buffers_per_shader_stage;
    posing.summary.max_compute_workgroup_storage_size = 4095;
    let workgroup = MethodOptions { stack: wavetrace::bvh::stack::BvhStack::Workgroup, ..Default::default() };
    let err = refusal(&posing, &workgroup);
    assert!(err.contains("max_compute_workgroup_storage_size") && err.contains("needs 4096 bytes"), "{err}");
    assert!(err.contains("--stack function") && err.contains("--workgroup-size of at most 63"), "{err}");
    // At the need, it renders.
    posing.summary.max_compute_workgroup_storage_size = 4096;
    render(Method::Megakernel, &scene, &s, &workgroup, Some(&posing), &|_| {}).unwrap();
}

/// A row of 4096 spheres along the view axis: a camera ray enters both children at every level
/// of the binary BVH and pushes the farther one, 10 entries deep, past the short stack's 8.
fn sphere_row() -> Scene {
    let spheres: Vec<String> = (0..4096)
        .map(|i| {
            format!(
                r#"{{"type": "sphere", "center": [0, 0, {}], "radius": 0.5, "material": "m"}}"#,
                -0.01 * i as f32
            )
        })
        .collect();
    let text = format!(
        r#"{{"format": "wavetrace-scene/1",
            "camera": {{"lookfrom": [0, 0, 5], "lookat": [0, 0, 0], "vup": [0, 1, 0], "vfov": 20,
                        "defocus_angle": 0, "focus_dist": 5}},
            "background": {{"type": "constant", "color": [0.5, 0.6, 0.8]}},
            "materials": {{"m": {{"type": "lambertian", "albedo": [0.5, 0.5, 0.5]}}}},
            "objects": [{}]}}"#,
        spheres.join(",")
    );
    wavetrace::scene::load::from_str(&text, "row.json", "sphere-row").unwrap()
}

/// `--stack workgroup` (8 entries a thread in workgroup memory, deeper ones spilled to function
/// memory) gives the function stack's film bit for bit: every layout on the megakernel and the
/// binary one on waves, on the sphere row (whose binary and Aila–Laine stacks spill: the CPU
/// twin's deepest stack is over 8); mesh-room (NEE's shadow rays) on the megakernel and
/// regenerate + tail.
#[test]
fn the_workgroup_stack_gives_the_function_stacks_film() {
    use wavetrace::bvh::stack::BvhStack;
    let row = sphere_row();
    let s = settings(false);
    for layout in [BvhLayout::Binary, BvhLayout::AilaLaine] {
        let opts = MethodOptions { bvh: layout, instrument: true, ..Default::default() };
        let deepest = run(Method::Cpu, &row, &s, &opts).traversal.unwrap().closest_hit.deepest_stack;
        assert!(deepest > 8, "{layout:?}: deepest stack {deepest}: the short stack would not spill");
    }
    if common::gpu().is_none() {
        return;
    }
    let room =
        Scene::resolve(concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json")).unwrap();
    let ways = common::gpu_ways();
    // The row on the megakernel in every layout and on waves; mesh-room (NEE's shadow rays) on
    // the megakernel and regenerate + tail.
    let mut cases: Vec<_> = LAYOUTS
        .iter()
        .map(|&bvh| (&row, false, ways[0].0, MethodOptions { bvh, ..ways[0].1.clone() }))
        .collect();
    cases.push((&row, false, ways[2].0, ways[2].1.clone()));
    cases.push((&room, true, ways[0].0, ways[0].1.clone()));
    cases.push((&room, true, ways[3].0, ways[3].1.clone()));
    for (scene, nee, method, opts) in cases {
        let function = run(method, scene, &settings(nee), &opts);
        let workgroup = MethodOptions { stack: BvhStack::Workgroup, ..opts.clone() };
        assert_eq!(
            run(method, scene, &settings(nee), &workgroup).film,
            function.film,
            "{}: {method:?} {opts:?}",
            scene.name
        );
    }
}

/// `wavetrace replay --bvh` replays the layout's traversal loop: on mesh-room the wide layout
/// issues fewer lockstep steps than the binary one (its nodes test 8 children a step), and the
/// JSON names the layout.
#[test]
fn replay_takes_the_layout() {
    let dir = crate::experiment::scratch("replay-bvh");
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json");
    let issued = |layout: &str| {
        let json = dir.join(format!("{layout}.json"));
        let args =
            ["replay", "--scene", room, "--bvh", layout, "--width", "32", "--height", "18", "--spp", "1"];
        let o = crate::experiment::wavetrace(
            &[
                &args[..],
                &[
                    "--nee",
                    "on",
                    "--methods",
                    "megakernel",
                    "--simd-width",
                    "8",
                    "--json",
                    json.to_str().unwrap(),
                ],
            ]
            .concat(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(v["bvh"], layout);
        v["methods"]["megakernel"]["widths"]["8"]["issued"].as_u64().unwrap()
    };
    let (binary, wide) = (issued("binary"), issued("wide"));
    assert!(wide < binary, "wide {wide} vs binary {binary} steps issued");
}
