//! What the wavefront's intersect pass costs beyond its traversal (issue 44, item 1b;
//! `wavetrace intersect-cost`). The same camera rays traced twice: by the wavefront's intersect
//! pass (waves at `--max-depth 1`, so its one bounce is the camera rays: each ray read from the
//! path state, its hit written back and queued), and by `intersect_registers`, which makes each
//! ray in place and keeps only a tally. Equal hits show they traced the same rays; the
//! difference in time per ray is what the path state around the traversal costs. The two take
//! turns after one untimed round (pipelines compiled, caches warm), as the experiment runner's
//! GPU variants do.

use anyhow::{anyhow, bail, Result};
use serde::Serialize;

use super::dispatch_cost::Spread;
use crate::gpu::context::{AdapterSummary, GpuContext};
use crate::gpu::label;
use crate::gpu::memory::MemoryLedger;
use crate::gpu::scene_buffers::SceneBuffers;
use crate::gpu::timing::{GpuTimer, Timing};
use crate::gpu::wavefront::intersect_registers::{IntersectRegisters, Tally};
use crate::gpu::wavefront::{Schedule, WavefrontOptions};
use crate::method::{self, Method, MethodOptions};
use crate::scene::Scene;
use crate::settings::RenderSettings;

pub const INTERSECT_COST_SCHEMA: &str = "wavetrace-intersect-cost/1";

/// One pass's figures over the repetitions.
#[derive(Clone, Debug, Serialize)]
pub struct PassCost {
    /// The pass's label (its row in a render's pass table).
    pub pass: &'static str,
    /// Camera rays that hit a primitive.
    pub hits: u64,
    /// GPU seconds over every camera ray (timestamps; None without them).
    pub seconds: Option<Spread>,
    /// The same per camera ray, in nanoseconds.
    pub ns_per_ray: Option<Spread>,
}

/// The measurement (`wavetrace intersect-cost --json`).
#[derive(Clone, Debug, Serialize)]
pub struct IntersectCostReport {
    pub schema: &'static str,
    pub build: crate::report::Build,
    pub machine: crate::report::Machine,
    pub adapter: AdapterSummary,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u32,
    pub workgroup_size: u32,
    /// The wavefront's pool (paths per wave) as it ran.
    pub pool: u32,
    pub repetitions: u32,
    /// Camera rays: width × height × spp.
    pub rays: u64,
    /// The wavefront's intersect pass over the camera rays.
    pub intersect: PassCost,
    /// `intersect_registers` over the same rays.
    pub registers: PassCost,
    /// The wrapping sum of (hit primitive + 1) over `intersect_registers`' hits.
    pub checksum: u32,
    /// Median registers time ÷ median intersect time (None without timestamps).
    pub registers_over_intersect: Option<f64>,
}

/// What to trace: the scene, the frame's camera rays, the wavefront's workgroup size and pool.
#[derive(Clone, Debug)]
pub struct IntersectCost {
    pub settings: RenderSettings,
    pub workgroup_size: u32,
    /// None: the wavefront's default pool for the adapter.
    pub pool_size: Option<u32>,
    pub repetitions: u32,
    /// Seconds of busy GPU work before each timed pass (`gpu::preheat`; none on a software
    /// adapter).
    pub preheat_seconds: f64,
}

/// Times both passes over `scene`'s camera rays; errors when their hits differ (then they did
/// not trace the same rays) or a repetition's tally differs from the first.
pub fn measure(ctx: &GpuContext, scene: &Scene, job: &IntersectCost) -> Result<IntersectCostReport> {
    let (settings, options) = camera_ray_render(job)?;
    let rays = settings.width as u64 * settings.height as u64 * settings.spp as u64;
    let rays32 =
        u32::try_from(rays).map_err(|_| anyhow!("{rays} camera rays: at most {} in one pass", u32::MAX))?;
    let (packed, camera) = method::prepare(Method::Wavefront, scene, &settings, &options)?;
    let frame = packed.frame_uniform(&camera, &settings);
    let mut memory = MemoryLedger::default();
    let scene_buffers = SceneBuffers::new(ctx, &packed, &frame, &settings, options.specialize, &mut memory)?;
    let registers = IntersectRegisters::new(
        ctx,
        &scene_buffers,
        rays32,
        settings.width * settings.height,
        job.workgroup_size,
        options.shader_checks,
    )?;

    let mut intersect_seconds = Vec::new();
    let mut registers_seconds = Vec::new();
    let mut intersect_hits = None;
    let mut tally: Option<Tally> = None;
    let mut pool = 0;
    for round in 0..=job.repetitions {
        let out = method::render(Method::Wavefront, scene, &settings, &options, Some(ctx), &|_| {})?;
        let hits = camera_ray_hits(&out, rays)?;
        if intersect_hits.is_some_and(|h| h != hits) {
            bail!("intersect's hits changed between repetitions: {intersect_hits:?}, then {hits}");
        }
        intersect_hits = Some(hits);
        pool = out.pool.unwrap_or(0);
        let mut timer = GpuTimer::new(ctx, Timing::Passes, job.preheat_seconds, &mut memory);
        let t = registers.trace(ctx, &scene_buffers, &mut timer)?;
        if tally.is_some_and(|first| first != t) {
            bail!("intersect_registers' tally changed between repetitions: {tally:?}, then {t:?}");
        }
        tally = Some(t);
        if round == 0 {
            continue; // untimed: pipelines compiled, caches warm
        }
        let timed = |timings: Option<&crate::gpu::timing::Timings>, pass: &str| {
            timings.filter(|t| t.per_pass()).and_then(|t| t.passes.get(pass)).map(|p| p.seconds)
        };
        intersect_seconds.extend(timed(out.timings.as_ref(), label::INTERSECT));
        registers_seconds.extend(timed(Some(&timer.into_timings()), label::INTERSECT_REGISTERS));
    }
    let (hits, tally) = (intersect_hits.unwrap_or(0), tally.expect("at least one round"));
    if hits != tally.hits {
        bail!(
            "intersect_registers found {} hits among the {rays} camera rays and intersect {hits}: they did not trace the same rays",
            tally.hits
        );
    }
    let cost = |pass, seconds: &[f64]| pass_cost(pass, hits, seconds, job.repetitions, rays);
    let intersect = cost(label::INTERSECT, &intersect_seconds);
    let registers = cost(label::INTERSECT_REGISTERS, &registers_seconds);
    let ratio = intersect.seconds.zip(registers.seconds).map(|(i, r)| r.median / i.median);
    Ok(IntersectCostReport {
        schema: INTERSECT_COST_SCHEMA,
        build: crate::report::Build::this(),
        machine: crate::report::Machine::this(),
        adapter: ctx.summary.clone(),
        scene: scene.name.clone(),
        width: settings.width,
        height: settings.height,
        spp: settings.spp,
        seed: settings.seed,
        workgroup_size: job.workgroup_size,
        pool,
        repetitions: job.repetitions,
        rays,
        intersect,
        registers,
        checksum: tally.checksum,
        registers_over_intersect: ratio,
    })
}

/// The render whose intersect pass is timed: one bounce, so the camera rays are all that
/// intersect traces, once each; the waves schedule, timed per pass.
fn camera_ray_render(job: &IntersectCost) -> Result<(RenderSettings, MethodOptions)> {
    if job.repetitions == 0 {
        bail!("--repetitions must be at least 1");
    }
    let settings = RenderSettings { max_depth: 1, nee: false, roulette: false, ..job.settings.clone() };
    settings.validate().map_err(anyhow::Error::msg)?;
    let options = MethodOptions {
        wavefront: WavefrontOptions {
            schedule: Schedule::Waves,
            workgroup_size: job.workgroup_size,
            pool_size: job.pool_size.map(crate::options::PoolSize::Paths),
            ..Default::default()
        },
        timing: Timing::Passes,
        preheat_seconds: job.preheat_seconds,
        ..Default::default()
    };
    Ok((settings, options))
}

/// The hits among the render's `rays` camera rays: every hit is queued at its material (or the
/// one shade queue) at bounce 0.
fn camera_ray_hits(out: &crate::method::RenderOutput, rays: u64) -> Result<u64> {
    let histogram =
        out.histogram.as_ref().ok_or_else(|| anyhow!("the waves render kept no queue histogram"))?;
    if histogram.rays.first().copied() != Some(rays) {
        bail!("intersect traced {:?} camera rays, not the frame's {rays}", histogram.rays.first());
    }
    Ok(histogram.materials.iter().filter_map(|m| m.first()).sum())
}

/// A pass's times, where every repetition timed it.
fn pass_cost(pass: &'static str, hits: u64, seconds: &[f64], repetitions: u32, rays: u64) -> PassCost {
    let timed = seconds.len() == repetitions as usize;
    PassCost {
        pass,
        hits,
        seconds: timed.then(|| Spread::of(seconds)),
        ns_per_ray: timed
            .then(|| Spread::of(&seconds.iter().map(|s| s * 1e9 / rays as f64).collect::<Vec<_>>())),
    }
}

impl IntersectCostReport {
    /// The table `wavetrace intersect-cost` prints.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut t = format!(
            "{} {}x{}x{}: {} camera rays, {} hits (checksum {:#010x}); {} ({}), median [min–max] of {} repetitions\n",
            self.scene,
            self.width,
            self.height,
            self.spp,
            self.rays,
            self.intersect.hits,
            self.checksum,
            self.adapter.name,
            self.adapter.backend,
            self.repetitions
        );
        let _ = writeln!(t, "{:<22} {:>32} {:>14}", "pass", "ns per camera ray", "GPU seconds");
        for p in [&self.intersect, &self.registers] {
            let ns = p.ns_per_ray.map_or("– (no timestamps)".to_string(), |s| {
                format!("{:.4} [{:.4}–{:.4}]", s.median, s.min, s.max)
            });
            let seconds = p.seconds.map_or("–".to_string(), |s| format!("{:.6}", s.median));
            let _ = writeln!(t, "{:<22} {:>32} {:>14}", p.pass, ns, seconds);
        }
        if let Some(r) = self.registers_over_intersect {
            let _ = writeln!(t, "intersect_registers / intersect: {r:.3}");
        }
        t
    }
}
