//! Pipelines are built once per device: a second render of the same method (an experiment's
//! next repetition) reuses every module and pipeline and renders the same film, and a render
//! that needs a different pipeline (another workgroup size) still gets its own.

use crate::common;

use wavetrace::gpu::wavefront::{Compaction, Schedule, Tail, WavefrontOptions};
use wavetrace::gpu::GpuContext;
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

#[test]
fn a_second_render_reuses_every_pipeline() {
    // Its own device, so that other tests' pipelines do not change the counts.
    if common::gpu().is_none() {
        return;
    }
    let ctx = GpuContext::new(std::env::var("WAVETRACE_ADAPTER").ok().as_deref()).unwrap();
    let scene = builtin::by_name("cornell").unwrap();
    let s = RenderSettings {
        width: 16,
        height: 12,
        spp: 2,
        max_depth: 4,
        seed: 3,
        accel: Accel::Bvh,
        nee: true,
        roulette: false,
    };
    let regenerate = WavefrontOptions {
        schedule: Schedule::Regenerate,
        tail: Tail::Megakernel,
        compaction: Compaction::Scan,
        ..Default::default()
    };
    let runs = [
        (Method::Megakernel, WavefrontOptions::default()),
        (Method::Wavefront, WavefrontOptions::default()),
        (Method::Wavefront, regenerate),
    ];
    for (method, wavefront) in runs {
        let what = format!("{method:?} {:?}", wavefront.schedule);
        let opts = MethodOptions { wavefront, ..Default::default() };
        let first = render(method, &scene, &s, &opts, Some(&ctx), &|_| {}).unwrap();
        let (built, hits) = (ctx.stages.pipelines(), ctx.stages.hits());
        let second = render(method, &scene, &s, &opts, Some(&ctx), &|_| {}).unwrap();
        assert_eq!(ctx.stages.pipelines(), built, "{what}: the second render built no pipeline");
        assert!(ctx.stages.hits() > hits, "{what}: the second render was served from the cache");
        assert_eq!(first.film.pixels, second.film.pixels, "{what}: the same film with cached pipelines");
    }
    // The control: a pipeline constant that differs (the workgroup size) is a new pipeline.
    let built = ctx.stages.pipelines();
    let wavefront = WavefrontOptions { workgroup_size: 32, ..Default::default() };
    let opts = MethodOptions { wavefront, ..Default::default() };
    render(Method::Wavefront, &scene, &s, &opts, Some(&ctx), &|_| {}).unwrap();
    assert!(ctx.stages.pipelines() > built, "another workgroup size builds its own pipelines");
}
