//! Runs an experiment: every planned run (or a shard's share) in turn, each as warm-up renders,
//! timed repetitions (GPU methods without per-pass timestamps), one render with per-pass
//! timestamps for the per-pass table, and an optional instrumented render, then its image, error
//! against the reference and record. `report.json` is rewritten atomically after every run; a run that fails
//! is recorded with its error and the others go on.

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context, Result};

use super::config::ExperimentConfig;
use super::error_map;
use super::gpu_slot::GpuSlot;
use super::outputs;
use super::plan::{self, RunSpec, Shard};
use super::reference::References;
use super::report::{
    now_rfc3339, Environment, ExperimentReport, PassStat, ReferenceRecord, ReportStatus, RunImages,
    RunRecord, RunStatus, Stat,
};
use super::resume::{self, Resume};
use crate::gpu::timing::Timing;
use crate::image_io::{self, RgbImage};
use crate::method::{self, MethodOptions};
use crate::metrics::{self, CompareOptions};
use crate::progress::Progress;
use crate::report::RunReport;

pub struct RunnerOptions {
    pub out_dir: PathBuf,
    pub shard: Option<Shard>,
    /// Where rendered references are cached.
    pub cache_dir: PathBuf,
    /// Whether to keep the finished runs of an earlier attempt in `out_dir`.
    pub resume: Resume,
}

/// Runs the config's runs (this shard's share; with `--resume`, those an earlier attempt did not
/// finish) and writes `report.json`, images, charts and `report.html` under `opts.out_dir`.
/// Errors only for what stops the whole experiment (the output directory cannot be written, an
/// earlier attempt that cannot be resumed); failed runs are in the report.
pub fn run(config: &ExperimentConfig, opts: &RunnerOptions) -> Result<ExperimentReport> {
    let out = &opts.out_dir;
    let planned = plan::plan(config);
    let selected: Vec<&RunSpec> = planned.iter().filter(|r| opts.shard.is_none_or(|s| s.takes(r))).collect();
    let fresh = ExperimentReport {
        schema: super::report::REPORT_SCHEMA.into(),
        status: ReportStatus::Running,
        name: config.name.clone(),
        question: config.question.clone(),
        config_file: config.file.display().to_string(),
        config: config.raw.clone(),
        environments: vec![Environment::this(opts.shard)?],
        runs_planned: planned.len(),
        runs_selected: selected.len(),
        missing_runs: Vec::new(),
        runs: Vec::new(),
        references: Vec::new(),
        charts: Vec::new(),
    };
    // Checked before anything is written, so a refused resume leaves the directory as it was.
    let mut report = resume::start(fresh, &planned, opts.shard, out, opts.resume)?;
    for sub in ["images", "references"] {
        std::fs::create_dir_all(out.join(sub))
            .with_context(|| format!("creating {}", out.join(sub).display()))?;
    }
    let env = report.environments.len() - 1;
    let kept: BTreeSet<usize> = report.runs.iter().map(|r| r.index).collect();
    let runs: Vec<&RunSpec> = selected.into_iter().filter(|r| !kept.contains(&r.index)).collect();
    // References of kept runs stay listed; those this process loads join them.
    let earlier_references = std::mem::take(&mut report.references);
    report.references = earlier_references.clone();
    report.write(out)?;

    let mut gpu = GpuSlot::new(config.adapter.clone());
    let mut references = References::new(opts.cache_dir.clone());
    // The bar counts path samples over every render of every run, so it moves within long runs.
    let total: u64 = runs.iter().map(|r| run_samples(config, r)).sum();
    let progress = Progress::new(total, &config.name);
    let mut done = 0;
    for (n, spec) in runs.iter().enumerate() {
        let what = format!("[{}/{}] {}", n + 1, runs.len(), spec.id);
        progress.set_message(&what);
        progress.println(&what);
        let bar = RunProgress { progress: &progress, base: done };
        let mut record = execute(config, spec, &mut gpu, &mut references, out, &bar);
        record.environment = env;
        done += run_samples(config, spec);
        progress.println(&summary_line(&record));
        report.runs.push(record);
        // Plan order, whichever attempt ran a run.
        report.runs.sort_by_key(|r| r.index);
        report.references = union_references(&earlier_references, references.records());
        report.environments[env].adapter = gpu.adapter.as_ref().map(serde_json::to_value).transpose()?;
        report.write(out)?;
        progress.set(done);
    }
    progress.finish();
    report.status = ReportStatus::Complete;
    report.environments[env].finished = Some(now_rfc3339());
    outputs::draw(&mut report, out)?;
    report.write(out)?;
    Ok(report)
}

/// `earlier` then the keys of `now` it lacks.
fn union_references(earlier: &[ReferenceRecord], now: Vec<ReferenceRecord>) -> Vec<ReferenceRecord> {
    let mut all = earlier.to_vec();
    for r in now {
        if all.iter().all(|e| e.key != r.key) {
            all.push(r);
        }
    }
    all
}

fn summary_line(r: &RunRecord) -> String {
    match r.status {
        RunStatus::Failed => format!("  FAILED: {}", r.error.as_deref().unwrap_or("?")),
        RunStatus::Ok => {
            let t = r.seconds.map_or("?".into(), |s| format!("{s:.4} s"));
            let src = if r.frame_seconds.is_some() { " frame" } else { " wall" };
            let err =
                r.error_metrics.as_ref().map_or(String::new(), |m| format!(", relMSE {:.3e}", m.relmse));
            format!("  ok: {t}{src}{err}")
        }
    }
}

/// Path samples a run renders: warm-ups, timed repetitions, the profiled render (per-pass
/// timestamps; none where the adapter has no timestamps, so the bar may end a render short) and
/// the instrumented render.
fn run_samples(config: &ExperimentConfig, spec: &RunSpec) -> u64 {
    let variant = &config.methods[spec.variant];
    let gpu = variant.method.needs_gpu();
    let instrumented = config.instrument && gpu;
    let profiled = gpu && variant.options.timing == Timing::Passes;
    let renders = u64::from(config.warmup)
        + u64::from(config.repetitions)
        + u64::from(profiled)
        + u64::from(instrumented);
    renders * spec.settings.sample_count()
}

/// Where a run's renders report their samples: the experiment's bar, from the samples of the
/// runs before it.
struct RunProgress<'a> {
    progress: &'a Progress,
    base: u64,
}

/// One run, never panicking: failures (and panics) become a failed record.
fn execute(
    config: &ExperimentConfig,
    spec: &RunSpec,
    gpu: &mut GpuSlot,
    refs: &mut References,
    out: &Path,
    bar: &RunProgress,
) -> RunRecord {
    let mut record = planned_record(config, spec);
    let result = catch_unwind(AssertUnwindSafe(|| measure(config, spec, gpu, refs, out, bar, &mut record)));
    let error = match result {
        Ok(Ok(())) => return record,
        Ok(Err(e)) => format!("{e:#}"),
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            format!("internal error (panic): {msg}")
        }
    };
    log::warn!("run {} failed: {error}", spec.id);
    if record.method == "megakernel" || record.method == "wavefront" {
        gpu.reset();
    }
    // Keep what is known about the run, drop half-filled measurements.
    let mut failed = planned_record(config, spec);
    failed.status = RunStatus::Failed;
    failed.error = Some(error);
    failed
}

fn planned_record(config: &ExperimentConfig, spec: &RunSpec) -> RunRecord {
    let v = &config.methods[spec.variant];
    let s = &spec.settings;
    RunRecord {
        index: spec.index,
        id: spec.id.clone(),
        environment: 0,
        scene: config.scenes[spec.scene].scene.name.clone(),
        width: s.width,
        height: s.height,
        spp: s.spp,
        max_depth: s.max_depth,
        nee: s.nee,
        seed: s.seed,
        accel: serde_json::to_value(s.accel)
            .ok()
            .and_then(|a| a.as_str().map(str::to_owned))
            .unwrap_or_default(),
        method: v.method.name().into(),
        label: v.label.clone(),
        options: method_options_json(v.method, &v.options),
        status: RunStatus::Ok,
        resumed: false,
        error: None,
        warmup: config.warmup,
        repetitions: config.repetitions,
        wall_seconds: None,
        gpu_seconds: None,
        frame_seconds: None,
        host_gap_seconds: None,
        between_passes_seconds: None,
        profiled_frame_seconds: None,
        time_source: None,
        seconds: None,
        passes: BTreeMap::new(),
        passes_per_bounce: BTreeMap::new(),
        queue_histogram: None,
        dispatches: None,
        empty_dispatches: None,
        iterations: None,
        idle_iterations: None,
        intersect_occupancy: None,
        samples: s.sample_count(),
        samples_per_second: None,
        rays: None,
        rays_per_second: None,
        invalid_samples: None,
        self_hits: None,
        shadow_self_hits: None,
        depth_cut: None,
        image_mean: None,
        repeatable: None,
        bytes_per_path: None,
        memory: None,
        pool_size: None,
        indirect_validation: None,
        simd: None,
        coherence: None,
        reference: None,
        error_metrics: None,
        efficiency: None,
        images: None,
    }
}

/// The knobs that apply to `method`, as the config spells them.
fn method_options_json(method: method::Method, o: &MethodOptions) -> serde_json::Value {
    use method::Method::*;
    let mut json = match method {
        Cpu | CpuF64 => serde_json::json!({
            "light_sampling": o.lights.sampling,
            "light_select": o.lights.select,
        }),
        Megakernel => serde_json::json!({
            "light_sampling": o.lights.sampling,
            "light_select": o.lights.select,
            "workgroup_size": o.megakernel.workgroup_size,
            "samples_per_dispatch": o.megakernel.samples_per_dispatch,
            "schedule": o.megakernel.schedule,
            "threads": o.megakernel.threads,
            "timing": o.timing,
        }),
        Wavefront => serde_json::json!({
            "light_sampling": o.lights.sampling,
            "light_select": o.lights.select,
            "workgroup_size": o.wavefront.workgroup_size,
            "pool_size": o.wavefront.pool_size,
            "compaction": o.wavefront.compaction,
            "shade": o.wavefront.shade,
            "schedule": o.wavefront.schedule,
            "sync_every": o.wavefront.sync_every,
            "tail": o.wavefront.tail,
            "tail_threshold": o.wavefront.tail_threshold,
            "chunk_pools": o.wavefront.chunk_pools,
            "scan": o.wavefront.scan,
            "append": o.wavefront.append,
            "queue_order": o.wavefront.queue_order,
            "refill_below": o.wavefront.refill_below,
            "compact_states": o.wavefront.compact_states,
            "ray_sort": o.wavefront.ray_sort,
            "timing": o.timing,
        }),
    };
    // Every method's numerical knobs and stress transform.
    let common = serde_json::json!({
        "ray_offset": o.numerics.ray_offset,
        "render_space": o.numerics.render_space,
        "sphere_hit": o.numerics.sphere_hit,
        "fresnel": o.numerics.fresnel,
        "scale": o.stress.scale,
        "translate": o.stress.translate,
    });
    if let (Some(map), serde_json::Value::Object(common)) = (json.as_object_mut(), common) {
        map.extend(common);
    }
    json
}

fn measure(
    config: &ExperimentConfig,
    spec: &RunSpec,
    gpu: &mut GpuSlot,
    refs: &mut References,
    out: &Path,
    bar: &RunProgress,
    rec: &mut RunRecord,
) -> Result<()> {
    let scene = &config.scenes[spec.scene].scene;
    let variant = &config.methods[spec.variant];
    let settings = &spec.settings;
    let reference = refs.get(config, scene, settings, &variant.options, gpu, out)?;
    let reference = reference.map(|r| (r.image.clone(), r.record.key.clone()));

    let ctx = if variant.method.needs_gpu() { Some(gpu.get()?) } else { None };
    let adapter = ctx.map(|c| &c.summary);
    // What `--schedule auto` chose on this adapter, as the run's options.
    rec.options = method_options_json(variant.method, &variant.options.resolve(variant.method, adapter));
    let renders_done = std::cell::Cell::new(0u64);
    let render = |options: &MethodOptions| {
        let start = bar.base + renders_done.get() * settings.sample_count();
        renders_done.set(renders_done.get() + 1);
        let progress = bar.progress;
        method::render(variant.method, scene, settings, options, ctx, &|d| progress.set(start + d))
    };

    // Per-pass timestamps are a profiler: on some drivers each one waits for the work before it
    // (llvmpipe: a wavefront frame of 23,500 passes took 2.7-4.0 s with them, 1.5-1.9 s
    // without), which charges the method with the most passes. So the timed repetitions run
    // without them, and one more repetition, not timed, gives the per-pass table.
    let profile = ctx.is_some_and(|c| c.summary.timestamps) && variant.options.timing == Timing::Passes;
    let timed = MethodOptions {
        timing: if profile { Timing::Frame } else { variant.options.timing },
        ..variant.options.clone()
    };
    for _ in 0..config.warmup {
        render(&timed)?;
    }
    let mut reports: Vec<RunReport> = Vec::new();
    let mut image: Option<Vec<f32>> = None;
    let mut repeatable = true;
    let mut same_image = |rgb: Vec<f32>| match &image {
        None => image = Some(rgb),
        Some(first) => repeatable &= first.iter().map(|v| v.to_bits()).eq(rgb.iter().map(|v| v.to_bits())),
    };
    for _ in 0..config.repetitions {
        let o = render(&timed)?;
        same_image(o.film.mean_rgb());
        reports.push(RunReport::new(scene, variant.method, settings, &timed, adapter, &o));
    }
    let profiled = if profile {
        let o = render(&variant.options)?;
        same_image(o.film.mean_rgb());
        Some(RunReport::new(scene, variant.method, settings, &variant.options, adapter, &o))
    } else {
        None
    };
    let image =
        RgbImage { width: settings.width, height: settings.height, data: image.expect("repetitions >= 1") };

    // Times: median over the timed repetitions; per-pass times, and the split of the frame they
    // allow, from the profiled one where there is one, else from the timed repetitions.
    let wall: Vec<f64> = reports.iter().map(|r| r.wall_seconds).collect();
    let frame_times: Vec<f64> = reports.iter().filter_map(|r| r.frame_seconds).collect();
    rec.wall_seconds = Stat::of(&wall);
    rec.frame_seconds = Stat::of(&frame_times);
    let gaps: Vec<f64> = reports.iter().filter_map(|r| r.host_gap_seconds).collect();
    rec.host_gap_seconds = Stat::of(&gaps).map(|s| s.median);
    let pass_reports = profiled.as_ref().map_or(&reports[..], std::slice::from_ref);
    let gpu_times: Vec<f64> = pass_reports.iter().filter_map(|r| r.gpu_seconds).collect();
    rec.gpu_seconds = Stat::of(&gpu_times);
    rec.profiled_frame_seconds = profiled.as_ref().and_then(|p| p.frame_seconds);
    rec.between_passes_seconds = match &profiled {
        Some(p) => p.between_passes_seconds,
        None => {
            let timed_per_pass = reports.iter().all(|r| r.between_passes_seconds.is_some());
            rec.frame_seconds
                .as_ref()
                .zip(rec.gpu_seconds.as_ref())
                .zip(rec.host_gap_seconds)
                .filter(|_| timed_per_pass)
                .map(|((f, g), h)| f.median - g.median - h)
        }
    };
    // The headline time: the frame's, host round trips included.
    let seconds = rec
        .frame_seconds
        .as_ref()
        .filter(|g| g.median > 0.0)
        .map_or(rec.wall_seconds.as_ref().map(|w| w.median), |g| Some(g.median));
    rec.seconds = seconds;
    let median_rep = {
        let key = |r: &RunReport| r.frame_seconds.unwrap_or(r.wall_seconds);
        let mut order: Vec<usize> = (0..reports.len()).collect();
        order.sort_by(|&a, &b| key(&reports[a]).total_cmp(&key(&reports[b])));
        &reports[order[order.len() / 2]]
    };
    let pass_rep = profiled.as_ref().unwrap_or(median_rep);
    let labels: std::collections::BTreeSet<&str> =
        pass_reports.iter().flat_map(|r| r.passes.keys().copied()).collect();
    for label in labels {
        let times: Vec<f64> =
            pass_reports.iter().map(|r| r.passes.get(label).map_or(0.0, |p| p.seconds)).collect();
        let passes = pass_rep.passes.get(label).map_or(0, |p| p.passes);
        rec.passes
            .insert(label.to_string(), PassStat { seconds: Stat::of(&times).expect("non-empty"), passes });
    }
    rec.passes_per_bounce =
        pass_rep.passes_per_bounce.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    rec.time_source =
        pass_rep.time_source.and_then(|t| serde_json::to_value(t).ok()?.as_str().map(str::to_owned));
    rec.queue_histogram = median_rep.queue_histogram.clone();
    rec.dispatches = Some(median_rep.dispatches);
    rec.empty_dispatches = median_rep.empty_dispatches;
    if let Some(s) = &median_rep.schedule {
        rec.iterations = Some(s.iterations);
        rec.idle_iterations = Some(s.idle_iterations);
        rec.intersect_occupancy = Some(s.intersect_occupancy);
    }
    rec.rays = Some(median_rep.rays);
    if let Some(s) = seconds.filter(|&s| s > 0.0) {
        rec.samples_per_second = Some(rec.samples as f64 / s);
        rec.rays_per_second = Some(median_rep.rays as f64 / s);
    }
    rec.invalid_samples = Some(median_rep.invalid_samples);
    rec.self_hits = Some(median_rep.failures.self_hits);
    rec.shadow_self_hits = Some(median_rep.failures.shadow_self_hits);
    rec.depth_cut = Some(median_rep.failures.depth_cut);
    rec.image_mean = Some(median_rep.image_mean);
    rec.repeatable = Some(repeatable);
    rec.bytes_per_path = median_rep.bytes_per_path;
    rec.memory = median_rep.memory.clone();
    rec.pool_size = median_rep.pool_size;
    rec.indirect_validation = median_rep.indirect_validation;

    // SIMD efficiency comes from a separate render: the counters' atomics would skew the times.
    if config.instrument && ctx.is_some_and(|c| c.summary.subgroups) {
        let options = MethodOptions { instrument: true, ..variant.options.clone() };
        let instrumented = render(&options)?;
        rec.simd = instrumented.simd;
        rec.coherence = instrumented.coherence;
    }

    // Images and error.
    let exr = format!("images/{}.exr", spec.id);
    let png = format!("images/{}.png", spec.id);
    image_io::write_exr(out.join(&exr), &image, &median_rep.exr_attributes())?;
    image_io::write_png(out.join(&png), &image)?;
    let mut error_map = None;
    if let Some((ref_image, key)) = reference {
        let opts = CompareOptions { trim: config.metrics.trim, flip: config.metrics.flip };
        let m = metrics::compare(&image, &ref_image, &opts).map_err(|e| anyhow!("error metrics: {e}"))?;
        rec.efficiency = seconds.filter(|&s| s > 0.0 && m.relmse > 0.0).map(|s| 1.0 / (m.relmse * s));
        rec.error_metrics = Some(m);
        rec.reference = Some(key);
        let map = format!("images/{}-error.png", spec.id);
        let rgb = error_map::relative_error_map(&image, &ref_image);
        image_io::write_png_rgb8(out.join(&map), image.width, image.height, &rgb)?;
        error_map = Some(map);
    }
    rec.images = Some(RunImages { exr, png, error_map });
    Ok(())
}
