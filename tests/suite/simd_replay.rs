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
