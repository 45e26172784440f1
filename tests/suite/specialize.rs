//! `--specialize` (issue 44): shaders compiled with only the scene's primitive, material and
//! texture kinds give the films of shaders with every kind compiled in, bit for bit, in both
//! megakernels and the wavefront's schedules; and a scene of one kind of each (the minimal
//! masks) renders with every pass that binds the scene.

use crate::common;

use wavetrace::gpu::specialize::Specialize;
use wavetrace::gpu::wavefront::{
    CompactStates, Compaction, RaySort, Schedule, ShadePasses, Tail, WavefrontOptions,
};
use wavetrace::method::{render, Method, MethodOptions, RenderOutput};
use wavetrace::scene::Scene;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(nee: bool) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 20,
        spp: 2,
        max_depth: 50,
        seed: 5,
        accel: Accel::Bvh,
        nee,
        roulette: false,
    }
}

fn run(method: Method, scene: &Scene, s: &RenderSettings, opts: &MethodOptions) -> RenderOutput {
    render(method, scene, s, opts, common::gpu(), &|_| {}).unwrap()
}

/// Renders `scene` with `opts` specialized and unspecialized and asserts the films are equal.
fn assert_same_film(method: Method, scene: &Scene, s: &RenderSettings, opts: &MethodOptions) {
    let specialized = run(method, scene, s, &MethodOptions { specialize: Specialize::Scene, ..opts.clone() });
    let every_kind = run(method, scene, s, &MethodOptions { specialize: Specialize::None, ..opts.clone() });
    assert_eq!(specialized.resolved.specialize, Specialize::Scene);
    assert_eq!(every_kind.resolved.specialize, Specialize::None);
    assert_eq!(specialized.film, every_kind.film, "{}: {method:?} {opts:?}", scene.name);
}

/// Every material and texture kind among the scenes: rtiow-kinds-8 has the three scattering
/// materials and every texture (solid, checker and the eight costly patterns) on spheres; Cornell
/// emitters and quads (with NEE and its MIS weights); mesh-room every shape and material, checker
/// and marble but no noise.
#[test]
fn specialized_shaders_give_the_films_of_every_kind_compiled_in() {
    if common::gpu().is_none() {
        return;
    }
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json");
    // Each scene meets one megakernel way and one wavefront way, the ways in turn (every way
    // meets a scene): a scene's specialized pipelines are compiled per way, which is most of this
    // test's cost on a software driver with a cold shader cache.
    for (i, (name, nee)) in
        [("rtiow-kinds-8", false), ("cornell", true), (room, true)].into_iter().enumerate()
    {
        let scene = Scene::resolve(name).unwrap();
        for (method, opts) in common::gpu_ways().into_iter().skip(i % 2).step_by(2) {
            assert_same_film(method, &scene, &settings(nee), &opts);
        }
    }
}

/// The furnace is one diffuse, untextured sphere: every mask has one kind, so no pass branches
/// on a kind. Every pass that binds the scene still renders it as with every kind compiled in:
/// the four ways to trace, and the wavefront's shade with one pass, its scan, its ray sort and
/// its state compaction.
#[test]
fn a_scene_of_one_kind_each_renders_with_every_pass() {
    if common::gpu().is_none() {
        return;
    }
    let scene = Scene::resolve("furnace").unwrap();
    let s = settings(true);
    let mut variants = common::gpu_ways();
    let waves = WavefrontOptions { schedule: Schedule::Waves, ..Default::default() };
    variants.push((
        Method::Wavefront,
        MethodOptions {
            wavefront: WavefrontOptions {
                compaction: Compaction::Scan,
                shade: ShadePasses::Single,
                ray_sort: RaySort::OctantCell,
                ..waves
            },
            ..Default::default()
        },
    ));
    variants.push((
        Method::Wavefront,
        MethodOptions {
            wavefront: WavefrontOptions {
                schedule: Schedule::Regenerate,
                tail: Tail::Megakernel,
                compact_states: CompactStates::On,
                ..waves
            },
            ..Default::default()
        },
    ));
    for (method, opts) in variants {
        assert_same_film(method, &scene, &s, &opts);
    }
    // Not a black film: the sphere and the light around it (exact: 0.5 and 1) were traced.
    let film = run(Method::Megakernel, &scene, &s, &MethodOptions::default()).film;
    let mean = film.image_mean();
    assert!(mean > 0.4 && mean <= 1.0, "furnace mean {mean}");
}
