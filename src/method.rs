//! The rendering methods and the one entry point that runs any of them.

use crate::bvh::BvhSummary;
use crate::camera::CameraFrame;
use crate::cpu;
use crate::cpu::traversal_counts::TraversalCounts;
use crate::film::Film;
use crate::gpu::instrument::{Coherence, SimdEfficiency};
use crate::gpu::megakernel::{self, MegakernelOptions};
use crate::gpu::memory::GpuMemory;
use crate::gpu::timing::{Measure, Timings};
use crate::gpu::wavefront::{self, QueueHistogram, ScheduleStats};
use crate::gpu::GpuContext;
use crate::gpu::GpuRender;
use crate::numerics::Failures;
pub use crate::options::{Method, MethodOptions};
use crate::packed_scene::PackedScene;
use crate::render_space::RenderSpace;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use anyhow::{anyhow, Result};
use std::collections::BTreeMap;
use std::time::Instant;

/// A finished render: the film and how long it took.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    pub film: Film,
    /// Host time from the start of the method (scene upload and pipeline creation included for
    /// GPU methods) to the film being on the host.
    pub wall_seconds: f64,
    /// GPU pass times (None for CPU methods).
    pub timings: Option<Timings>,
    /// GPU compute passes dispatched, empty ones included (0 for CPU methods).
    pub dispatches: u64,
    /// Of those, indirect dispatches sized to zero workgroups (GPU methods).
    pub empty_dispatches: Option<u64>,
    /// Compute passes the dispatches were recorded in (GPU methods).
    pub compute_passes: Option<u64>,
    /// SIMD efficiency per instrumented point (`instrument` only).
    pub simd: Option<BTreeMap<String, SimdEfficiency>>,
    /// GPU memory per path in flight (None for CPU methods).
    pub bytes_per_path: Option<u64>,
    /// GPU memory the render allocated, by category (None for CPU methods).
    pub memory: Option<GpuMemory>,
    /// Paths in flight (wavefront only).
    pub pool: Option<u32>,
    /// Paths per queue per bounce (wavefront, waves with compaction only).
    pub histogram: Option<QueueHistogram>,
    /// The intersect pass's coherence per iteration bucket (wavefront, `--instrument`).
    pub coherence: Option<Vec<Coherence>>,
    /// The wavefront's schedule and what it cost (wavefront only).
    pub schedule: Option<ScheduleStats>,
    /// Self-hits and paths cut by the depth limit (NaN/Inf samples: `film.invalid_samples()`).
    pub failures: Failures,
    /// The options as they ran, every knob resolved at run time made concrete (what reports
    /// record: `auto` never stands for what ran).
    pub resolved: MethodOptions,
    /// Host seconds to prepare the scene for the render: the move into render space and the
    /// packing, the acceleration structure (BVH) build above all; before the render's clock.
    pub scene_seconds: f64,
    /// The BVH the render traversed: layout, nodes, bytes, depth.
    pub bvh: BvhSummary,
    /// Host seconds of its build (binary SAH, then the layout's conversion): part of
    /// `scene_seconds`.
    pub bvh_seconds: f64,
    /// Traversal counts per ray on the CPU twin's paths (`--instrument`, every method).
    pub traversal: Option<TraversalCounts>,
}

impl RenderOutput {
    /// The render's time as the runner measures it: the frame's (first submission to last
    /// completion) for GPU methods, else the wall clock's.
    pub fn seconds(&self) -> f64 {
        self.timings.as_ref().map(|t| t.frame_seconds).filter(|&s| s > 0.0).unwrap_or(self.wall_seconds)
    }

    /// Seconds of preheat before the frame (GPU methods; 0 without one).
    pub fn preheat_seconds(&self) -> f64 {
        self.timings.as_ref().map_or(0.0, |t| t.preheat_seconds)
    }

    fn from_gpu(r: GpuRender, resolved: MethodOptions, scene_seconds: f64, bvh: (BvhSummary, f64)) -> Self {
        Self {
            film: r.film,
            wall_seconds: r.wall_seconds,
            timings: Some(r.timings),
            dispatches: r.dispatches,
            empty_dispatches: r.empty_dispatches,
            compute_passes: Some(r.compute_passes),
            simd: r.simd,
            bytes_per_path: Some(r.bytes_per_path),
            memory: Some(r.memory),
            pool: None,
            histogram: None,
            coherence: None,
            schedule: None,
            failures: r.failures,
            resolved,
            scene_seconds,
            bvh: bvh.0,
            bvh_seconds: bvh.1,
            traversal: None,
        }
    }
}

/// The scene as `method` renders it: moved into render space with the stress transform, packed
/// with the light and numerics options, and its camera frame. The SIMD replay records its paths
/// on this, so that they are the device's paths.
pub fn prepare(
    method: Method,
    scene: &Scene,
    settings: &RenderSettings,
    options: &MethodOptions,
) -> Result<(PackedScene, CameraFrame)> {
    // The stress transform and the move into render space, as one f64 transform before the
    // scene is stored in f32. cpu-f64, the ground truth, always renders camera-relative: its
    // stand-in for a scene kept in f64 end to end (in f64, rendering about the camera differs
    // from rendering in world coordinates by ~1e-16 of the distance).
    let space = if method == Method::CpuF64 { RenderSpace::Camera } else { options.numerics.render_space };
    let transform = space.transform(options.stress, &scene.camera);
    let scene = &transform.apply(scene).map_err(anyhow::Error::msg)?;
    if settings.accel == crate::settings::Accel::None && options.bvh != crate::bvh::BvhLayout::Binary {
        anyhow::bail!(
            "--accel none (one leaf: the linear loop) takes --bvh binary only, not --bvh {}",
            options.bvh.name()
        );
    }
    crate::options::check_bvh(options).map_err(|e| anyhow!(e.for_cli()))?;
    let packed = PackedScene::new(scene, settings.accel)
        .with_bvh(options.bvh, options.collapse)
        .map_err(|e| anyhow!("scene {}: {e}", scene.name))?
        .with_stack(options.stack)
        .with_light_options(options.lights)
        .with_numerics(options.numerics)
        .with_stress(transform);
    let camera = CameraFrame::new(&scene.camera, settings.width, settings.height);
    Ok((packed, camera))
}

/// Renders `scene` with `method`. `on_progress` receives the number of path samples finished.
pub fn render(
    method: Method,
    scene: &Scene,
    settings: &RenderSettings,
    options: &MethodOptions,
    gpu: Option<&GpuContext>,
    on_progress: &(dyn Fn(u64) + Sync),
) -> Result<RenderOutput> {
    settings.validate().map_err(anyhow::Error::msg)?;
    let built = Instant::now();
    let (packed, camera) = prepare(method, scene, settings, options)?;
    let scene_seconds = built.elapsed().as_secs_f64();
    let bvh = (packed.bvh.summary(&packed.nodes), packed.bvh.build_seconds);
    let traversal = options.instrument.then(|| cpu::traversal_counts::count(&packed, &camera, settings));
    // A scene whose f32 arithmetic would overflow renders silently wrong: refuse it instead.
    if method != Method::CpuF64 {
        crate::arithmetic_range::check_f32(&packed, &camera)
            .map_err(|e| anyhow!("{} computes in f32: {e}", method.name()))?;
    }
    let start = Instant::now();
    match method {
        Method::Cpu | Method::CpuF64 => {
            let (film, failures) = render_cpu(method, &packed, &camera, settings, on_progress);
            Ok(RenderOutput {
                film,
                wall_seconds: start.elapsed().as_secs_f64(),
                timings: None,
                dispatches: 0,
                empty_dispatches: None,
                compute_passes: None,
                simd: None,
                bytes_per_path: None,
                memory: None,
                pool: None,
                histogram: None,
                coherence: None,
                schedule: None,
                failures,
                resolved: options.clone(),
                scene_seconds,
                bvh: bvh.0,
                bvh_seconds: bvh.1,
                traversal,
            })
        }
        Method::Megakernel => {
            let ctx = gpu.ok_or_else(|| anyhow!("--method megakernel needs a GPU adapter"))?;
            let r = megakernel::render(
                ctx,
                &packed,
                &camera,
                settings,
                &options.megakernel,
                measure(options),
                on_progress,
            )?;
            let megakernel = MegakernelOptions { threads: r.threads, ..options.megakernel.resolve() };
            let resolved = MethodOptions { megakernel, ..options.clone() };
            Ok(RenderOutput { traversal, ..RenderOutput::from_gpu(r, resolved, scene_seconds, bvh) })
        }
        Method::Wavefront => {
            let ctx = gpu.ok_or_else(|| anyhow!("--method wavefront needs a GPU adapter"))?;
            let r = wavefront::render(
                ctx,
                &packed,
                &camera,
                settings,
                &options.wavefront,
                measure(options),
                on_progress,
            )?;
            Ok(RenderOutput {
                pool: Some(r.pool),
                histogram: r.histogram,
                coherence: r.coherence,
                schedule: Some(r.schedule),
                traversal,
                ..RenderOutput::from_gpu(
                    r.render,
                    MethodOptions { wavefront: r.resolved, ..options.clone() },
                    scene_seconds,
                    bvh,
                )
            })
        }
    }
}

/// The CPU reference's film, in the method's precision, reporting samples done row by row.
fn render_cpu(
    method: Method,
    packed: &PackedScene,
    camera: &CameraFrame,
    settings: &RenderSettings,
    on_progress: &(dyn Fn(u64) + Sync),
) -> (Film, Failures) {
    let done = std::sync::atomic::AtomicU64::new(0);
    let row_samples = settings.width as u64 * settings.spp as u64;
    let on_row = || {
        let d = done.fetch_add(row_samples, std::sync::atomic::Ordering::Relaxed) + row_samples;
        on_progress(d);
    };
    if method == Method::Cpu {
        cpu::render::<f32>(packed, camera, settings, &on_row)
    } else {
        cpu::render::<f64>(packed, camera, settings, &on_row)
    }
}

/// What a GPU method measures besides the film.
fn measure(options: &MethodOptions) -> Measure {
    Measure {
        instrument: options.instrument,
        timing: options.timing,
        shader_checks: options.shader_checks,
        specialize: options.specialize,
        preheat_seconds: options.preheat_seconds,
    }
}
