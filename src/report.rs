//! The JSON record of one render (`--report`): what ran, where, how long, and how it went, so a
//! figure can be traced back to its run.

use crate::gpu::context::AdapterSummary;
use crate::gpu::instrument::{Coherence, SimdEfficiency};
use crate::gpu::memory::GpuMemory;
use crate::gpu::timing::{PassTime, TimeSource};
use crate::gpu::wavefront::{QueueHistogram, ScheduleStats};
use crate::method::{Method, MethodOptions, RenderOutput};
use crate::numerics::Failures;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use serde::Serialize;
use std::collections::BTreeMap;

pub const RUN_SCHEMA: &str = "wavetrace-run/1";

#[derive(Clone, Debug, Serialize)]
pub struct Machine {
    pub hostname: String,
    pub os: String,
    pub cpu: String,
    pub logical_cores: usize,
}

impl Machine {
    pub fn this() -> Self {
        let read = |p: &str| std::fs::read_to_string(p).unwrap_or_default();
        let cpu = read("/proc/cpuinfo")
            .lines()
            .find_map(|l| {
                l.strip_prefix("model name").map(|r| r.trim_start_matches([' ', '\t', ':']).to_string())
            })
            .unwrap_or_else(|| std::env::consts::ARCH.to_string());
        Self {
            hostname: read("/etc/hostname").trim().to_string(),
            os: std::env::consts::OS.to_string(),
            cpu,
            logical_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Build {
    pub version: &'static str,
    /// The commit the binary was built from.
    pub git_commit: &'static str,
}

impl Build {
    pub fn this() -> Self {
        Self { version: env!("CARGO_PKG_VERSION"), git_commit: env!("WAVETRACE_GIT_COMMIT") }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct SceneSummary {
    pub name: String,
    pub spheres: usize,
    /// Spheres, quads and mesh triangles.
    pub primitives: usize,
    pub materials: usize,
    /// Host seconds to prepare the scene for this render, the BVH build above all.
    pub prepare_seconds: f64,
    /// The BVH traversed (`--bvh`): layout, nodes, bytes, depth.
    pub bvh: crate::bvh::BvhSummary,
    /// Host seconds of the BVH's build (part of `prepare_seconds`).
    pub bvh_build_seconds: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    pub schema: &'static str,
    pub build: Build,
    pub machine: Machine,
    /// None for CPU methods.
    pub adapter: Option<AdapterSummary>,
    pub scene: SceneSummary,
    pub method: Method,
    pub settings: RenderSettings,
    pub options: MethodOptions,
    pub wall_seconds: f64,
    /// Sum of pass times (None for CPU methods).
    pub gpu_seconds: Option<f64>,
    /// Wall clock from the first submission to the last completion (GPU methods): the headline
    /// time, since it includes the GPU idle while the host reads counters back between
    /// submissions, where the schedules differ.
    pub frame_seconds: Option<f64>,
    /// Frame time between a submission's completion and the next submission: the GPU idle
    /// while the host reads counters back and records (GPU methods).
    pub host_gap_seconds: Option<f64>,
    /// Submissions in the frame (GPU methods); `waits` counts those the host waited for.
    pub submissions: Option<u64>,
    /// Times the host waited for the GPU in the frame: all but the last inside it (GPU methods).
    pub waits: Option<u64>,
    /// Seconds of busy GPU work just before the frame's first submission (`gpu::preheat`; not
    /// part of the frame; 0 when none ran).
    pub preheat_seconds: Option<f64>,
    /// `frame_seconds` − `gpu_seconds` − `host_gap_seconds`: the GPU's time between its timed
    /// passes inside a submission (launches, barriers, cache flushes: a fixed cost per pass);
    /// with per-pass timestamps only.
    pub between_passes_seconds: Option<f64>,
    pub time_source: Option<TimeSource>,
    pub passes: BTreeMap<&'static str, PassTime>,
    /// Compute passes dispatched, empty ones included (GPU methods).
    pub dispatches: u64,
    /// Indirect dispatches the GPU sized to zero workgroups (GPU methods).
    pub empty_dispatches: Option<u64>,
    /// Compute passes the dispatches were recorded in (GPU methods; fewer than `dispatches`
    /// with `--compute-passes shared`).
    pub compute_passes: Option<u64>,
    /// The wavefront's schedule: shares, iterations (idle ones apart), intersect occupancy.
    pub schedule: Option<ScheduleStats>,
    pub samples: u64,
    /// Samples per second of frame time (GPU methods), else of wall time.
    pub samples_per_second: f64,
    /// Rays traced (closest-hit queries, camera rays included), counted per path by every method.
    pub rays: u64,
    /// Rays per second, of the same time as `samples_per_second`.
    pub rays_per_second: f64,
    /// NaN/Inf samples dropped instead of accumulated.
    pub invalid_samples: u64,
    /// Where the numerics failed: `self_hits` (secondary rays whose closest hit was the primitive
    /// they left), `shadow_self_hits` (shadow rays likewise) and `depth_cut` (paths cut by
    /// `max_depth`), as top-level fields beside `invalid_samples`.
    #[serde(flatten)]
    pub failures: Failures,
    pub image_mean: f64,
    /// GPU memory per path in flight, bytes (GPU methods).
    pub bytes_per_path: Option<u64>,
    /// GPU memory the render allocated, by category, and the peak (GPU methods).
    pub memory: Option<GpuMemory>,
    /// Paths in flight (wavefront).
    pub pool_size: Option<u32>,
    /// Seconds per bounce of the passes that run once per bounce (wavefront).
    pub passes_per_bounce: BTreeMap<&'static str, Vec<f64>>,
    /// Paths in each queue at each bounce, summed over waves (wavefront with compaction).
    pub queue_histogram: Option<QueueHistogram>,
    /// SIMD efficiency (active / available subgroup lanes) per pass or point (`--instrument`).
    pub simd: Option<BTreeMap<String, SimdEfficiency>>,
    /// Traversal counts per ray on the CPU twin's paths (`--instrument`; issue 59).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traversal: Option<crate::cpu::traversal_counts::TraversalCounts>,
    /// The intersect pass's coherence per iteration bucket (wavefront, `--instrument`; issue 26).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coherence: Option<Vec<Coherence>>,
    /// Whether wgpu inserted its validation dispatch before every indirect dispatch
    /// (`InstanceFlags::VALIDATION_INDIRECT_CALL`, wgpu #5714).
    pub indirect_validation: Option<bool>,
    /// The untimed renders before this one (`render --warmup`): policy, frames, seconds,
    /// whether it settled, each frame's time (and the GPU's state where NVML reads it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warmup: Option<crate::warmup::WarmupLog>,
}

impl RunReport {
    pub fn new(
        scene: &Scene,
        method: Method,
        settings: &RenderSettings,
        adapter: Option<&AdapterSummary>,
        out: &RenderOutput,
    ) -> Self {
        let gpu_seconds = out.timings.as_ref().map(|t| t.total_seconds());
        let frame_seconds = out.timings.as_ref().map(|t| t.frame_seconds);
        let samples = settings.sample_count();
        let seconds = out.seconds();
        Self {
            schema: RUN_SCHEMA,
            build: Build::this(),
            machine: Machine::this(),
            adapter: adapter.cloned(),
            scene: SceneSummary {
                name: scene.name.clone(),
                spheres: scene.spheres.len(),
                primitives: scene.primitive_count(),
                materials: scene.materials.len(),
                prepare_seconds: out.scene_seconds,
                bvh: out.bvh.clone(),
                bvh_build_seconds: out.bvh_seconds,
            },
            method,
            settings: settings.clone(),
            // What ran: every knob resolved at run time made concrete.
            options: out.resolved.clone(),
            wall_seconds: out.wall_seconds,
            gpu_seconds,
            frame_seconds,
            host_gap_seconds: out.timings.as_ref().map(|t| t.host_gap_seconds),
            submissions: out.timings.as_ref().map(|t| t.submissions),
            waits: out.timings.as_ref().map(|t| t.waits),
            preheat_seconds: out.timings.as_ref().map(|t| t.preheat_seconds),
            between_passes_seconds: out
                .timings
                .as_ref()
                .filter(|t| t.per_pass())
                .map(|t| t.frame_seconds - t.total_seconds() - t.host_gap_seconds),
            time_source: out.timings.as_ref().map(|t| t.source),
            passes: out.timings.as_ref().map(|t| t.passes.clone()).unwrap_or_default(),
            dispatches: out.dispatches,
            empty_dispatches: out.empty_dispatches,
            compute_passes: out.compute_passes,
            schedule: out.schedule.clone(),
            samples,
            samples_per_second: samples as f64 / seconds,
            rays: out.film.rays(),
            rays_per_second: out.film.rays() as f64 / seconds,
            invalid_samples: out.film.invalid_samples(),
            failures: out.failures,
            image_mean: out.film.image_mean(),
            bytes_per_path: out.bytes_per_path,
            memory: out.memory.clone(),
            pool_size: out.pool,
            passes_per_bounce: out.timings.as_ref().map(|t| t.per_bounce.clone()).unwrap_or_default(),
            queue_histogram: out.histogram.clone(),
            simd: out.simd.clone(),
            traversal: out.traversal,
            coherence: out.coherence.clone(),
            indirect_validation: adapter.map(|a| a.indirect_validation),
            warmup: None,
        }
    }

    /// The `wavetrace.*` header attributes of the run's EXR: what ran, with every knob of every
    /// method (`ray_offset`, `sphere_hit`, `fresnel` as the CLI spells them; `scale` and
    /// `translate` as `--scale` and `--translate` read them back, exactly).
    pub fn exr_attributes(&self) -> Vec<(String, String)> {
        let s = &self.settings;
        let n = &self.options.numerics;
        let t = &self.options.stress;
        [
            ("method", self.method.name().to_string()),
            ("scene", self.scene.name.clone()),
            ("spp", s.spp.to_string()),
            ("max_depth", s.max_depth.to_string()),
            ("seed", s.seed.to_string()),
            ("nee", if s.nee { "on" } else { "off" }.to_string()),
            // The rule, not just on: a report says which roulette its paths ended by.
            ("roulette", if s.roulette { "pbrt-v4" } else { "off" }.to_string()),
            ("light_sampling", self.options.lights.sampling.name().to_string()),
            ("light_select", self.options.lights.select.name().to_string()),
            ("ray_offset", n.ray_offset.name()),
            ("sphere_hit", n.sphere_hit.name().to_string()),
            ("fresnel", n.fresnel.name().to_string()),
            ("render_space", n.render_space.name().to_string()),
            ("scale", format!("{:?}", t.scale)),
            ("translate", t.translate.map(|c| format!("{c:?}")).join(",")),
            ("render_time_s", format!("{:.6}", self.wall_seconds)),
            ("git_commit", self.build.git_commit.to_string()),
        ]
        .into_iter()
        .map(|(k, v)| (format!("wavetrace.{k}"), v))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
    use crate::scene::stress::StressTransform;

    /// The knobs reach the EXR attributes in a form the CLI reads back, and the failure counters
    /// sit beside `invalid_samples` in the `--report` JSON.
    #[test]
    fn knobs_and_failures_are_recorded() {
        let scene = crate::scene::builtin::by_name("three-spheres").unwrap();
        let settings = RenderSettings { width: 4, height: 2, spp: 1, ..RenderSettings::default() };
        let options = MethodOptions {
            numerics: NumericOptions {
                ray_offset: RayOffset::Tmin(1e-4),
                sphere_hit: SphereHit::Book,
                fresnel: Fresnel::Exact,
                render_space: crate::render_space::RenderSpace::World,
            },
            stress: StressTransform { scale: 1e-4, translate: [1e5, -2.5, 0.1] },
            ..MethodOptions::default()
        };
        let mut out = crate::method::render(Method::Cpu, &scene, &settings, &options, None, &|_| {}).unwrap();
        out.failures = Failures { self_hits: 3, shadow_self_hits: 2, depth_cut: 1 };
        let report = RunReport::new(&scene, Method::Cpu, &settings, None, &out);
        let attrs = report.exr_attributes();
        let attr = |k: &str| attrs.iter().find(|(n, _)| n == &format!("wavetrace.{k}")).unwrap().1.clone();
        assert_eq!(RayOffset::parse(&attr("ray_offset")), Ok(RayOffset::Tmin(1e-4)));
        assert_eq!(attr("sphere_hit"), "book");
        assert_eq!(attr("fresnel"), "exact");
        assert_eq!(StressTransform::parse_scale(&attr("scale")), Ok(1e-4));
        assert_eq!(StressTransform::parse_translate(&attr("translate")), Ok([1e5, -2.5, 0.1]));
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["self_hits"], 3);
        assert_eq!(json["shadow_self_hits"], 2);
        assert_eq!(json["depth_cut"], 1);
        assert_eq!(json["invalid_samples"], 0);
        assert_eq!(json["options"]["ray_offset"], "tmin=1e-4");
        assert_eq!(json["options"]["sphere_hit"], "book");
        assert_eq!(json["options"]["fresnel"], "exact");
        assert_eq!(json["options"]["scale"], 1e-4);
        assert_eq!(json["options"]["translate"], serde_json::json!([1e5, -2.5, 0.1]));
    }
}
