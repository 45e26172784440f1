//! Work-weighted SIMD efficiency (issue 25): the counters inside the BVH traversal loop and the
//! pooled per-pass and frame figures, on every GPU method with and without NEE.

use crate::common;

use wavetrace::gpu::instrument::{FRAME_KEY, WORK_PREFIX};
use wavetrace::gpu::schedule::Schedule;
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(nee: bool) -> RenderSettings {
    RenderSettings { width: 24, height: 16, spp: 2, max_depth: 8, seed: 5, accel: Accel::Bvh, nee }
}

/// (label, method, options) of every GPU method, instrumented.
fn methods() -> Vec<(&'static str, Method, MethodOptions)> {
    let mut regenerate = MethodOptions { instrument: true, ..Default::default() };
    regenerate.megakernel.schedule = Schedule::Regenerate;
    regenerate.megakernel.threads = Some(256);
    vec![
        ("megakernel", Method::Megakernel, MethodOptions { instrument: true, ..Default::default() }),
        ("regenerate", Method::Megakernel, regenerate),
        ("wavefront", Method::Wavefront, MethodOptions { instrument: true, ..Default::default() }),
    ]
}

/// Every traversal is counted step by step; the work-weighted figures pool those steps, so they
/// lie below the entry points where traversal diverges, and the frame figure exists.
#[test]
fn traversal_steps_are_counted_and_pooled() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        return;
    }
    for (scene, nee) in [("rtiow-final", false), ("cornell", true)] {
        let s = settings(nee);
        let scene_data = builtin::by_name(scene).unwrap();
        for (label, method, opts) in methods() {
            let what = format!("{scene} nee={nee} {label}");
            let out = render(method, &scene_data, &s, &opts, Some(ctx), &|_| {}).unwrap();
            let simd = out.simd.unwrap();
            let (traverse, shadow, entry, pass) = match method {
                Method::Wavefront => ("intersect_traverse", "shadow_traverse", "intersect", "intersect"),
                _ => ("megakernel_traverse", "megakernel_shadow_traverse", "megakernel_bounce", "megakernel"),
            };
            for kind in ["inner", "leaf", "primitive"] {
                let k = format!("{traverse}_{kind}");
                assert!(simd.contains_key(&k), "{what}: {k} counted: {simd:?}");
                // Rays take several steps each: more subgroup-iterations than arrivals.
                assert!(simd[&k].subgroups > simd[entry].subgroups / 2, "{what}: {k}");
                if nee {
                    assert!(simd[&format!("{shadow}_{kind}")].subgroups > 0, "{what}: {shadow}");
                }
            }
            if !nee {
                assert!(!simd.keys().any(|k| k.contains("shadow")), "{what}: no shadow rays without NEE");
            }
            let work = simd[&format!("{WORK_PREFIX}{pass}")];
            let frame = simd[FRAME_KEY];
            assert!(frame.efficiency > 0.0 && frame.efficiency <= 1.0, "{what}: {frame:?}");
            // Lanes whose rays finished traversal idle while others step on.
            assert!(
                simd[&format!("{traverse}_inner")].efficiency < simd[entry].efficiency,
                "{what}: traversal {:?} vs entry {:?}",
                simd[&format!("{traverse}_inner")],
                simd[entry]
            );
            assert!(work.efficiency < simd[entry].efficiency, "{what}: work {work:?} vs entry");
            let issued: u64 = simd
                .iter()
                .filter(|(k, _)| !k.starts_with(WORK_PREFIX) && *k != FRAME_KEY)
                .map(|(_, e)| e.subgroups)
                .sum();
            assert_eq!(frame.subgroups, issued, "{what}: the frame pools every point");
        }
    }
}

/// The replay at the device's subgroup width reproduces the device's counters within 3
/// percentage points, slot by slot and pooled, for the naive megakernel with and without NEE.
#[test]
fn megakernel_replay_matches_the_device() {
    use wavetrace::camera::CameraFrame;
    use wavetrace::packed_scene::PackedScene;
    use wavetrace::replay::megakernel::{replay, Launch};
    let Some(ctx) = common::gpu() else { return };
    let w = ctx.summary.subgroup_min_size;
    if !ctx.summary.subgroups || w != ctx.summary.subgroup_max_size {
        return; // a width the driver picks per pipeline cannot be replayed as one
    }
    for (scene, nee) in [("rtiow-final", false), ("cornell", true), ("spheres-64", false)] {
        let s = settings(nee);
        let scene_data = builtin::by_name(scene).unwrap();
        let opts = MethodOptions { instrument: true, ..Default::default() };
        let device =
            render(Method::Megakernel, &scene_data, &s, &opts, Some(ctx), &|_| {}).unwrap().simd.unwrap();
        let packed = PackedScene::new(&scene_data, s.accel);
        let frame = CameraFrame::new(&scene_data.camera, s.width, s.height);
        let launch = Launch {
            samples_per_dispatch: opts.megakernel.samples_per_dispatch,
            max_threads: 65535 * opts.megakernel.workgroup_size,
            every: 1,
        };
        let r = replay(&packed, &frame, &s, &[w], launch);
        let replayed = r.counts[0].1.efficiencies().unwrap();
        let keys = |m: &std::collections::BTreeMap<String, _>| m.keys().cloned().collect::<Vec<_>>();
        assert_eq!(keys(&device), keys(&replayed), "{scene}: the same blocks run");
        for (k, d) in &device {
            let r = replayed[k];
            assert!((d.efficiency - r.efficiency).abs() <= 0.03, "{scene} {k}: device {d:?} replay {r:?}");
        }
    }
}

/// `wavetrace replay` refuses widths no subgroup has, saying why, and runs without a GPU.
#[test]
fn replay_cli_refuses_bad_widths() {
    for bad in ["0", "24", "256"] {
        let out = std::process::Command::new(common::bin())
            .args(["replay", "--scene", "three-spheres", "--width", "8", "--height", "8", "--spp", "1"])
            .args(["--simd-width", bad])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("power of two from 1 to 128"), "{bad}: {err}");
    }
    let out = std::process::Command::new(common::bin())
        .args(["replay", "--scene", "three-spheres", "--width", "8", "--height", "8", "--spp", "1"])
        .args(["--simd-width", "4,32"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("W=4") && text.contains("W=32"), "{text}");
}
