//! What a GPU render's times say. The headline is the frame time, from the first submission to
//! the last completion, so it includes the GPU idle while the host reads counters back between
//! submissions (where the wavefront's schedules differ); the sum of passes leaves that out, and
//! the run record splits what it leaves out: `host_gap_seconds` (completion to next submission)
//! and `between_passes_seconds` (the rest: the GPU's time between its timed passes; negative
//! where passes overlapped).
//! Without timestamps no pass is given a time it was not measured to take.

use crate::common;

use wavetrace::gpu::timing::{TimeSource, Timing, FRAME_LABEL};
use wavetrace::gpu::wavefront::{Schedule, WavefrontOptions};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::report::RunReport;
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

#[test]
fn the_frame_time_holds_the_passes_and_the_host_gaps() {
    let Some(ctx) = common::gpu() else { return };
    let scene = builtin::by_name("rtiow-final").unwrap();
    let s = RenderSettings {
        width: 40,
        height: 24,
        spp: 8,
        max_depth: 50,
        seed: 1,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    };
    let regenerate = WavefrontOptions { schedule: Schedule::Regenerate, ..Default::default() };
    for (method, wavefront) in [
        (Method::Megakernel, WavefrontOptions::default()),
        (Method::Wavefront, WavefrontOptions::default()),
        (Method::Wavefront, regenerate),
    ] {
        for timing in [Timing::Passes, Timing::Frame] {
            let opts = MethodOptions { wavefront, timing, ..Default::default() };
            let out = render(method, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
            let r = RunReport::new(&scene, method, &s, Some(&ctx.summary), &out);
            let what = format!("{method:?} {:?} {timing:?}", wavefront.schedule);
            let (frame, gpu) = (r.frame_seconds.unwrap(), r.gpu_seconds.unwrap());
            assert!(frame > 0.0 && gpu > 0.0, "{what}: frame {frame}, passes {gpu}");
            // Not `frame >= gpu`: passes without a barrier between them may overlap (seen on
            // llvmpipe: the megakernel's passes summed to 0.021 s in a 0.017 s frame), so the
            // host gap can be negative; the frame is still the time the job took.
            assert!(frame <= r.wall_seconds, "{what}: the frame lies within the render's wall time");
            let gap = r.host_gap_seconds.unwrap();
            assert!((0.0..=frame).contains(&gap), "{what}: host gaps {gap} in a {frame} s frame");
            if method == Method::Wavefront && wavefront.schedule == Schedule::Regenerate {
                let waits = out.timings.as_ref().unwrap().waits;
                if timing == Timing::Passes {
                    // Per-pass timestamps are read back batch by batch: the host waits at each.
                    assert!(gap > 0.0, "{what}: timed passes wait on the host between batches");
                } else {
                    // The GPU decides at each check (issue 42): the only wait is the frame's end.
                    assert_eq!((gap, waits), (0.0, 1), "{what}: no host gap inside the frame");
                }
            }
            let t = out.timings.as_ref().unwrap();
            if t.per_pass() {
                assert_eq!(r.between_passes_seconds, Some(frame - gpu - gap), "{what}");
            } else {
                assert_eq!(r.between_passes_seconds, None, "{what}: no passes timed, nothing between");
            }
            assert_eq!(
                r.samples_per_second,
                s.sample_count() as f64 / frame,
                "{what}: the headline is the frame"
            );
            let t = out.timings.unwrap();
            if t.source == TimeSource::Timestamps {
                // Every second of the sum is some pass's own: no `frame` row beside them.
                assert!(!t.passes.contains_key(FRAME_LABEL), "{what}: {:?}", t.passes.keys());
            }
            if timing == Timing::Frame || t.source == TimeSource::WallClock {
                // Counted, not timed: only `frame` has a time.
                for (label, p) in &t.passes {
                    assert!(
                        *label == FRAME_LABEL || p.seconds == 0.0,
                        "{what}: {label} was given {}",
                        p.seconds
                    );
                }
                assert!(t.per_bounce.is_empty(), "{what}: times per bounce without timestamps");
            }
        }
    }
}

/// The preheat keeps the GPU busy for about the time asked, outside the frame: a frame is
/// preheated on a GPU and never on a software adapter, and the report says which.
#[test]
fn the_preheat_runs_for_the_time_asked_and_outside_the_frame() {
    let Some(ctx) = common::gpu() else { return };
    // Callable on any adapter (a GPU renderer skips it on a software one).
    let t = wavetrace::gpu::preheat::run(ctx, 0.05).unwrap();
    assert!((0.05..5.0).contains(&t), "a 0.05 s preheat took {t} s");
    assert_eq!(wavetrace::gpu::preheat::run(ctx, 0.0).unwrap(), 0.0);
    assert!(
        wavetrace::options::check_preheat(11.0).is_err() && wavetrace::options::check_preheat(0.2).is_ok()
    );
    let scene = builtin::by_name("three-spheres").unwrap();
    let s = RenderSettings {
        width: 16,
        height: 8,
        spp: 2,
        max_depth: 8,
        seed: 1,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    };
    let opts = MethodOptions { preheat_seconds: 0.3, timing: Timing::Frame, ..Default::default() };
    let out = render(Method::Megakernel, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
    let r = RunReport::new(&scene, Method::Megakernel, &s, Some(&ctx.summary), &out);
    let preheat = r.preheat_seconds.expect("a GPU render reports its preheat");
    if ctx.summary.is_software() {
        assert_eq!(preheat, 0.0, "no preheat on a software adapter");
    } else {
        assert!(preheat >= 0.3, "asked for 0.3 s, preheated {preheat} s");
        assert!(r.frame_seconds.unwrap() < out.wall_seconds - 0.29, "the preheat is not part of the frame");
    }
}
