//! Runs an experiment: every planned run (or a shard's share), in groups: the GPU variants of one
//! job take turns (`interleave`), every other run goes alone. Each run warms up (timed by
//! default for GPU methods), then the group's timed repetitions go round-robin (GPU methods
//! without per-pass timestamps), then each run renders once with per-pass timestamps for the
//! per-pass table and optionally once instrumented, and gets its image, error against the
//! reference, spread (`stability.rs`) and record. `report.json` is rewritten atomically after
//! every group; a run that fails is recorded with its error and the others go on.

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
use crate::method;
use crate::metrics::{self, CompareOptions};
use crate::options::MethodOptions;
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
        overrides: config.overrides.clone(),
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
    // The bar counts path samples over the timed, profiled and instrumented renders of every
    // run (and fixed warm-ups), so it moves within long runs.
    let total: u64 = runs.iter().map(|r| run_samples(config, r)).sum();
    let progress = Progress::new(total, &config.name);
    let mut done = 0;
    let mut started = 0;
    for group in groups(config, &runs) {
        for spec in &group {
            started += 1;
            let what = format!("[{started}/{}] {}", runs.len(), spec.id);
            progress.set_message(&what);
            progress.println(&what);
        }
        let bar = GroupBar { progress: &progress, done: std::cell::Cell::new(done) };
        let records = run_group(config, &group, &mut gpu, &mut references, out, &bar);
        done += group.iter().map(|r| run_samples(config, r)).sum::<u64>();
        for mut record in records {
            record.environment = env;
            progress.println(&summary_line(&record));
            report.runs.push(record);
        }
        // Plan order, whichever attempt ran a run.
        report.runs.sort_by_key(|r| r.index);
        report.references = union_references(&earlier_references, references.records());
        report.environments[env].adapter = gpu.adapter.as_ref().map(serde_json::to_value).transpose()?;
        report.environments[env].gpu_state_source = gpu.state_source();
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

/// The runs to do, in groups whose timed repetitions take turns (`interleave`): the GPU
/// variants of one job (scene and settings) form one group, in plan order. CPU runs, and every
/// run without `interleave`, are groups of one: a CPU render between two GPU repetitions would
/// let the GPU's clocks drop, which is what taking turns is meant to even out.
fn groups<'a>(config: &ExperimentConfig, runs: &[&'a RunSpec]) -> Vec<Vec<&'a RunSpec>> {
    let mut out: Vec<Vec<&'a RunSpec>> = Vec::new();
    for &r in runs {
        let gpu = |s: &RunSpec| config.methods[s.variant].method.needs_gpu();
        let joins = |g: &Vec<&RunSpec>| gpu(g[0]) && g[0].scene == r.scene && g[0].settings == r.settings;
        match out.iter_mut().find(|g| config.interleave && gpu(r) && joins(g)) {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
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

/// `  [3] ok: 0.1234 s frame, spread 1.2%, relMSE …` (the index tells apart the runs of a
/// group, whose lines come together), with a warning where the time is not steady.
fn summary_line(r: &RunRecord) -> String {
    match r.status {
        RunStatus::Failed => format!("  [{}] FAILED: {}", r.index, r.error.as_deref().unwrap_or("?")),
        RunStatus::Ok => {
            let t = r.seconds.map_or("?".into(), |s| format!("{s:.4} s"));
            let src = if r.frame_seconds.is_some() { " frame" } else { " wall" };
            let spread =
                r.stability.as_ref().and_then(|s| Some((s.spread?, s))).map_or(String::new(), |(x, s)| {
                    format!(", spread {:.1}%", 100.0 * x) + if s.unstable { " (unstable)" } else { "" }
                });
            let cold = if r.stability.as_ref().is_some_and(|s| s.cold) { ", cold (no warm-up)" } else { "" };
            let err =
                r.error_metrics.as_ref().map_or(String::new(), |m| format!(", relMSE {:.3e}", m.relmse));
            format!("  [{}] ok: {t}{src}{spread}{cold}{err}", r.index)
        }
    }
}

/// Path samples the bar counts for a run: fixed warm-ups (a timed warm-up's are not known
/// before), timed repetitions, the profiled render (per-pass timestamps; none where the adapter
/// has no timestamps, so the bar may end a render short) and the instrumented render.
fn run_samples(config: &ExperimentConfig, spec: &RunSpec) -> u64 {
    let variant = &config.methods[spec.variant];
    let gpu = variant.method.needs_gpu();
    let instrumented = config.instrument && gpu;
    let profiled = gpu && variant.options.timing == Timing::Passes;
    let renders = u64::from(config.warmup.policy(variant.method).planned_frames())
        + u64::from(config.repetitions)
        + u64::from(profiled)
        + u64::from(instrumented);
    renders * spec.settings.sample_count()
}

/// Where a group's renders report their samples: the experiment's bar, from the samples done
/// before each render.
struct GroupBar<'a> {
    progress: &'a Progress,
    done: std::cell::Cell<u64>,
}

/// A group's runs (one, or the GPU variants of a job taking turns), never panicking: each run
/// that fails (or panics) becomes a failed record and the others go on. In order: references
/// and options; each run's warm-up; the timed repetitions, run by run within each round; then
/// each run's profiled and instrumented renders, image and error.
fn run_group(
    config: &ExperimentConfig,
    group: &[&RunSpec],
    gpu: &mut GpuSlot,
    refs: &mut References,
    out: &Path,
    bar: &GroupBar,
) -> Vec<RunRecord> {
    let mut runs: Vec<Run> = group.iter().map(|s| Run::new(config, s)).collect();
    if runs.len() > 1 {
        let indices: Vec<usize> = group.iter().map(|s| s.index).collect();
        for r in &mut runs {
            r.record.interleaved_with = indices.iter().copied().filter(|&i| i != r.spec.index).collect();
        }
    }
    for r in &mut runs {
        r.attempt(gpu, |r, gpu| r.prepare(gpu, refs, out));
    }
    // Warm-up work counts towards the next run's warm-up: the device is the same and has not
    // idled in between.
    let mut shared = 0.0;
    for r in &mut runs {
        r.attempt(gpu, |r, gpu| r.warm_up(gpu, bar, shared));
        shared += r.record.warmup_log.as_ref().map_or(0.0, |w| w.work_seconds());
    }
    for rep in 0..config.repetitions {
        for r in &mut runs {
            r.attempt(gpu, |r, gpu| r.timed_render(gpu, bar, rep));
        }
    }
    for r in &mut runs {
        r.attempt(gpu, |r, gpu| r.finish(gpu, out, bar));
    }
    runs.into_iter().map(Run::into_record).collect()
}

/// One run on its way through its group's phases.
struct Run<'a> {
    config: &'a ExperimentConfig,
    spec: &'a RunSpec,
    scene: &'a crate::scene::Scene,
    variant: &'a super::config::MethodVariant,
    record: RunRecord,
    /// Why it failed; a failed run sits out the phases left.
    failed: Option<String>,
    /// The reference image and its key (None without a reference).
    reference: Option<(RgbImage, String)>,
    /// The options of its timed renders (per-pass timestamps off when a profiled render gives
    /// the per-pass table).
    timed: MethodOptions,
    /// Whether one more render, with per-pass timestamps, gives the per-pass table.
    profile: bool,
    reports: Vec<RunReport>,
    /// The first render's image; every later one must be bit-identical to it.
    image: Option<Vec<f32>>,
    repeatable: bool,
    state_before: Option<crate::gpu::state::GpuState>,
}

impl<'a> Run<'a> {
    fn new(config: &'a ExperimentConfig, spec: &'a RunSpec) -> Self {
        let variant = &config.methods[spec.variant];
        Run {
            config,
            spec,
            scene: &config.scenes[spec.scene].scene,
            variant,
            record: planned_record(config, spec),
            failed: None,
            reference: None,
            timed: variant.options.clone(),
            profile: false,
            reports: Vec::new(),
            image: None,
            repeatable: true,
            state_before: None,
        }
    }

    /// Runs one phase unless the run has failed; an error or a panic fails the run (and, on
    /// the GPU, drops the device: a lost or errored one cannot be trusted with the next render).
    fn attempt(&mut self, gpu: &mut GpuSlot, phase: impl FnOnce(&mut Self, &mut GpuSlot) -> Result<()>) {
        if self.failed.is_some() {
            return;
        }
        let result = catch_unwind(AssertUnwindSafe(|| phase(self, gpu)));
        let error = match result {
            Ok(Ok(())) => return,
            Ok(Err(e)) => format!("{e:#}"),
            // A requested stop is not this run's failure: it ends the whole experiment.
            Err(panic) if crate::cancel::is_cancelled(panic.as_ref()) => std::panic::resume_unwind(panic),
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                format!("internal error (panic): {msg}")
            }
        };
        log::warn!("run {} failed: {error}", self.spec.id);
        if self.variant.method.needs_gpu() {
            gpu.reset();
        }
        self.failed = Some(error);
    }

    /// The record: as measured, or, for a failed run, what is known about it with its error
    /// (half-filled measurements dropped).
    fn into_record(self) -> RunRecord {
        let Some(error) = self.failed else { return self.record };
        RunRecord {
            status: RunStatus::Failed,
            error: Some(error),
            interleaved_with: self.record.interleaved_with,
            ..planned_record(self.config, self.spec)
        }
    }

    /// Renders once with `options`; `counted` renders move the bar.
    fn render(
        &self,
        options: &MethodOptions,
        gpu: &mut GpuSlot,
        bar: &GroupBar,
        counted: bool,
    ) -> Result<method::RenderOutput> {
        let ctx = if self.variant.method.needs_gpu() { Some(gpu.get()?) } else { None };
        let start = bar.done.get();
        let progress = bar.progress;
        let out = method::render(self.variant.method, self.scene, &self.spec.settings, options, ctx, &|d| {
            // Where the Python package's Ctrl-C stops the experiment (`cancel.rs`): report.json
            // holds the groups that finished, and `--resume` renders the rest.
            crate::cancel::checkpoint();
            if counted {
                progress.set(start + d)
            }
        })?;
        if counted {
            bar.done.set(start + self.spec.settings.sample_count());
        }
        Ok(out)
    }

    /// The GPU's state now, for a GPU method's run where NVML reads it.
    fn gpu_state(&self, gpu: &GpuSlot) -> Option<crate::gpu::state::GpuState> {
        if self.variant.method.needs_gpu() {
            gpu.sample()
        } else {
            None
        }
    }

    fn adapter(&self, gpu: &GpuSlot) -> Option<crate::gpu::context::AdapterSummary> {
        if self.variant.method.needs_gpu() {
            gpu.adapter.clone()
        } else {
            None
        }
    }

    /// The reference, and the options as they will run on this adapter.
    fn prepare(&mut self, gpu: &mut GpuSlot, refs: &mut References, out: &Path) -> Result<()> {
        let config = self.config;
        let reference = refs.get(config, self.scene, &self.spec.settings, &self.variant.options, gpu, out)?;
        self.reference = reference.map(|r| (r.image.clone(), r.record.key.clone()));
        if self.variant.method.needs_gpu() {
            gpu.get()?;
        }
        let adapter = self.adapter(gpu);
        // What `--schedule auto` chose on this adapter, as the run's options.
        self.record.options = crate::options::knobs::view(
            self.variant.method,
            &self.variant.options.resolve(self.variant.method, adapter.as_ref().map(|a| a.is_software())),
        );
        // Per-pass timestamps are a profiler: on some drivers each one waits for the work
        // before it (llvmpipe: a wavefront frame of 23,500 passes took 2.7-4.0 s with them,
        // 1.5-1.9 s without), which charges the method with the most passes. So the timed
        // repetitions run without them, and one more render, not timed, gives the per-pass table.
        self.profile =
            adapter.as_ref().is_some_and(|a| a.timestamps) && self.variant.options.timing == Timing::Passes;
        self.timed = MethodOptions {
            timing: if self.profile { Timing::Frame } else { self.variant.options.timing },
            preheat_seconds: config.preheat_seconds,
            ..self.variant.options.clone()
        };
        Ok(())
    }

    /// Untimed renders until the policy is met; `shared` seconds of warm-up work were done just
    /// before by the group's other runs.
    fn warm_up(&mut self, gpu: &mut GpuSlot, bar: &GroupBar, shared: f64) -> Result<()> {
        let config = self.config;
        let policy = config.warmup.policy(self.variant.method);
        let counted = matches!(policy, crate::warmup::WarmupPolicy::Frames(_));
        let timed = self.timed.clone();
        let gpu = std::cell::RefCell::new(gpu);
        let log = crate::warmup::warm_up(
            &policy,
            shared,
            || {
                let o = self.render(&timed, &mut gpu.borrow_mut(), bar, counted)?;
                Ok((o.seconds(), o.preheat_seconds()))
            },
            || self.gpu_state(&gpu.borrow()),
        )?;
        self.record.warmup = log.frames;
        self.record.warmup_log = Some(log);
        Ok(())
    }

    /// One timed repetition (`rep` counts from 0), with the GPU's state read before the first
    /// and after the last.
    fn timed_render(&mut self, gpu: &mut GpuSlot, bar: &GroupBar, rep: u32) -> Result<()> {
        let config = self.config;
        if rep == 0 {
            self.state_before = self.gpu_state(gpu);
        }
        let timed = self.timed.clone();
        let o = self.render(&timed, gpu, bar, true)?;
        let after = if rep + 1 == config.repetitions { self.gpu_state(gpu) } else { None };
        self.same_image(o.film.mean_rgb());
        let adapter = self.adapter(gpu);
        if rep == 0 {
            // What the timed renders ran: every knob resolved at run time made concrete.
            self.record.options = crate::options::knobs::view(self.variant.method, &o.resolved);
        }
        self.reports.push(RunReport::new(
            self.scene,
            self.variant.method,
            &self.spec.settings,
            adapter.as_ref(),
            &o,
        ));
        if let (Some(before), Some(after)) = (self.state_before.clone(), after) {
            self.record.gpu_state = Some(crate::gpu::state::GpuStateSpan { before, after });
        }
        Ok(())
    }

    fn same_image(&mut self, rgb: Vec<f32>) {
        match &self.image {
            None => self.image = Some(rgb),
            Some(first) => {
                self.repeatable &= first.iter().map(|v| v.to_bits()).eq(rgb.iter().map(|v| v.to_bits()))
            }
        }
    }

    /// The profiled render, the statistics of the repetitions, the instrumented render, the
    /// image and its error.
    fn finish(&mut self, gpu: &mut GpuSlot, out: &Path, bar: &GroupBar) -> Result<()> {
        let config = self.config;
        let adapter = self.adapter(gpu);
        let profiled = if self.profile {
            let options =
                MethodOptions { preheat_seconds: config.preheat_seconds, ..self.variant.options.clone() };
            let o = self.render(&options, gpu, bar, true)?;
            self.same_image(o.film.mean_rgb());
            Some(RunReport::new(self.scene, self.variant.method, &self.spec.settings, adapter.as_ref(), &o))
        } else {
            None
        };
        // SIMD efficiency comes from a separate render: the counters' atomics would skew the times.
        let instrumented = if config.instrument && adapter.as_ref().is_some_and(|a| a.subgroups) {
            let options = MethodOptions { instrument: true, ..self.variant.options.clone() };
            Some(self.render(&options, gpu, bar, true)?)
        } else {
            None
        };
        let reports = std::mem::take(&mut self.reports);
        let settings = &self.spec.settings;
        let spec = self.spec;
        let reference = self.reference.take();
        let image = RgbImage {
            width: settings.width,
            height: settings.height,
            data: self.image.take().expect("repetitions >= 1"),
        };
        let repeatable = self.repeatable;
        let rec = &mut self.record;
        record_times(rec, &reports, profiled.as_ref());
        let median_rep = median_report(&reports);
        let pass_rep = profiled.as_ref().unwrap_or(median_rep);
        let pass_reports = profiled.as_ref().map_or(&reports[..], std::slice::from_ref);
        record_passes(rec, pass_reports, pass_rep);
        record_counts(rec, &reports, median_rep, pass_rep);
        rec.repeatable = Some(repeatable);

        rec.traversal = match &instrumented {
            Some(i) => i.traversal,
            // CPU methods and adapters without subgroups: counted without a render.
            None if config.instrument => {
                let options = &self.variant.options;
                let (packed, camera) =
                    crate::method::prepare(self.variant.method, self.scene, settings, options)?;
                Some(crate::cpu::traversal_counts::count(&packed, &camera, settings))
            }
            None => None,
        };
        if let Some(instrumented) = instrumented {
            rec.simd = instrumented.simd;
            rec.coherence = instrumented.coherence;
        }
        rec.stability = Some(super::stability::of_record(rec, config.unstable_spread));

        write_images(rec, out, config, &spec.id, &image, reference, &median_rep.exr_attributes())
    }
}

/// Times: median over the timed repetitions; per-pass times, and the split of the frame they
/// allow, from the profiled one where there is one, else from the timed repetitions; and the
/// headline time: the frame's, host round trips included.
fn record_times(rec: &mut RunRecord, reports: &[RunReport], profiled: Option<&RunReport>) {
    let wall: Vec<f64> = reports.iter().map(|r| r.wall_seconds).collect();
    let frame_times: Vec<f64> = reports.iter().filter_map(|r| r.frame_seconds).collect();
    rec.wall_seconds = Stat::of(&wall);
    rec.frame_seconds = Stat::of(&frame_times);
    let gaps: Vec<f64> = reports.iter().filter_map(|r| r.host_gap_seconds).collect();
    rec.host_gap_seconds = Stat::of(&gaps).map(|s| s.median);
    let pass_reports = profiled.map_or(reports, std::slice::from_ref);
    let gpu_times: Vec<f64> = pass_reports.iter().filter_map(|r| r.gpu_seconds).collect();
    rec.gpu_seconds = Stat::of(&gpu_times);
    rec.profiled_frame_seconds = profiled.and_then(|p| p.frame_seconds);
    rec.between_passes_seconds = match profiled {
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
    rec.seconds = rec
        .frame_seconds
        .as_ref()
        .filter(|g| g.median > 0.0)
        .map_or(rec.wall_seconds.as_ref().map(|w| w.median), |g| Some(g.median));
}

/// The repetition of median time (the frame's where timed, else the wall clock's).
fn median_report(reports: &[RunReport]) -> &RunReport {
    let key = |r: &RunReport| r.frame_seconds.unwrap_or(r.wall_seconds);
    let mut order: Vec<usize> = (0..reports.len()).collect();
    order.sort_by(|&a, &b| key(&reports[a]).total_cmp(&key(&reports[b])));
    &reports[order[order.len() / 2]]
}

/// Per-pass times over `pass_reports`, with the pass counts and split of `pass_rep`.
fn record_passes(rec: &mut RunRecord, pass_reports: &[RunReport], pass_rep: &RunReport) {
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
}

/// The counts of the median repetition: dispatches, schedule, rays, failures, memory.
fn record_counts(rec: &mut RunRecord, reports: &[RunReport], median_rep: &RunReport, pass_rep: &RunReport) {
    rec.queue_histogram = median_rep.queue_histogram.clone();
    rec.dispatches = Some(median_rep.dispatches);
    rec.empty_dispatches = median_rep.empty_dispatches;
    rec.compute_passes = median_rep.compute_passes;
    rec.submissions = median_rep.submissions;
    rec.waits = median_rep.waits;
    let prepare: Vec<f64> = reports.iter().map(|r| r.scene.prepare_seconds).collect();
    rec.scene_prepare_seconds = Stat::of(&prepare).map(|s| s.median);
    let bvh_build: Vec<f64> = reports.iter().map(|r| r.scene.bvh_build_seconds).collect();
    rec.bvh_build_seconds = Stat::of(&bvh_build).map(|s| s.median);
    rec.bvh = Some(median_rep.scene.bvh.clone());
    rec.preheat_seconds = median_rep.preheat_seconds;
    if let Some(s) = &median_rep.schedule {
        rec.iterations = Some(s.iterations);
        rec.idle_iterations = Some(s.idle_iterations);
        rec.blocking_reads = Some(s.blocking_reads);
        rec.speculative_iterations = Some(s.speculative_iterations);
        rec.intersect_occupancy = Some(s.intersect_occupancy);
        // The profiled render's, where there is one: the same counts, with pass times.
        let profiled = pass_rep.schedule.as_ref().and_then(|p| p.state_traffic.clone());
        rec.state_traffic = profiled.or_else(|| s.state_traffic.clone());
    }
    rec.rays = Some(median_rep.rays);
    if let Some(s) = rec.seconds.filter(|&s| s > 0.0) {
        rec.samples_per_second = Some(rec.samples as f64 / s);
        rec.rays_per_second = Some(median_rep.rays as f64 / s);
    }
    rec.invalid_samples = Some(median_rep.invalid_samples);
    rec.self_hits = Some(median_rep.failures.self_hits);
    rec.shadow_self_hits = Some(median_rep.failures.shadow_self_hits);
    rec.depth_cut = Some(median_rep.failures.depth_cut);
    rec.image_mean = Some(median_rep.image_mean);
    rec.bytes_per_path = median_rep.bytes_per_path;
    rec.memory = median_rep.memory.clone();
    rec.pool_size = median_rep.pool_size;
    rec.indirect_validation = median_rep.indirect_validation;
}

/// Writes the image (EXR and PNG) and, against a reference, its error metrics and map.
fn write_images(
    rec: &mut RunRecord,
    out: &Path,
    config: &ExperimentConfig,
    id: &str,
    image: &RgbImage,
    reference: Option<(RgbImage, String)>,
    attributes: &[(String, String)],
) -> Result<()> {
    let exr = format!("images/{id}.exr");
    let png = format!("images/{id}.png");
    image_io::write_exr(out.join(&exr), image, attributes)?;
    image_io::write_png(out.join(&png), image)?;
    let mut error_map = None;
    if let Some((ref_image, key)) = reference {
        let opts = CompareOptions { trim: config.metrics.trim, flip: config.metrics.flip };
        let m = metrics::compare(image, &ref_image, &opts).map_err(|e| anyhow!("error metrics: {e}"))?;
        rec.efficiency = rec.seconds.filter(|&s| s > 0.0 && m.relmse > 0.0).map(|s| 1.0 / (m.relmse * s));
        rec.error_metrics = Some(m);
        rec.reference = Some(key);
        let map = format!("images/{id}-error.png");
        let rgb = error_map::relative_error_map(image, &ref_image);
        image_io::write_png_rgb8(out.join(&map), image.width, image.height, &rgb)?;
        error_map = Some(map);
    }
    rec.images = Some(RunImages { exr, png, error_map });
    Ok(())
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
        roulette: s.roulette,
        seed: s.seed,
        accel: serde_json::to_value(s.accel)
            .ok()
            .and_then(|a| a.as_str().map(str::to_owned))
            .unwrap_or_default(),
        method: v.method.name().into(),
        label: v.label.clone(),
        options: crate::options::knobs::view(v.method, &v.options),
        status: RunStatus::Ok,
        resumed: false,
        error: None,
        warmup: config.warmup.policy(v.method).planned_frames(),
        repetitions: config.repetitions,
        warmup_log: None,
        interleaved_with: Vec::new(),
        stability: None,
        gpu_state: None,
        wall_seconds: None,
        gpu_seconds: None,
        frame_seconds: None,
        host_gap_seconds: None,
        submissions: None,
        waits: None,
        blocking_reads: None,
        speculative_iterations: None,
        scene_prepare_seconds: None,
        bvh: None,
        bvh_build_seconds: None,
        preheat_seconds: None,
        between_passes_seconds: None,
        profiled_frame_seconds: None,
        time_source: None,
        seconds: None,
        passes: BTreeMap::new(),
        passes_per_bounce: BTreeMap::new(),
        queue_histogram: None,
        dispatches: None,
        empty_dispatches: None,
        compute_passes: None,
        iterations: None,
        idle_iterations: None,
        intersect_occupancy: None,
        state_traffic: None,
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
        traversal: None,
        reference: None,
        error_metrics: None,
        efficiency: None,
        images: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(interleave: bool) -> ExperimentConfig {
        let text = serde_json::json!({
            "schema": "wavetrace-experiment/1",
            "question": "q",
            "scenes": ["three-spheres"],
            "resolutions": ["8x8"],
            "spp": [1, 2],
            "interleave": interleave,
            "methods": [
                {"method": "megakernel"},
                {"method": "cpu"},
                {"method": "wavefront"}
            ]
        });
        ExperimentConfig::from_str(&text.to_string(), Path::new("t.json")).unwrap()
    }

    #[test]
    fn gpu_variants_of_a_job_form_one_group_and_cpu_runs_go_alone() {
        let c = config(true);
        let planned = plan::plan(&c);
        let runs: Vec<&RunSpec> = planned.iter().collect();
        let indices: Vec<Vec<usize>> =
            groups(&c, &runs).iter().map(|g| g.iter().map(|r| r.index).collect()).collect();
        // Plan order: spp 1 (megakernel 0, cpu 1, wavefront 2), spp 2 (3, 4, 5).
        assert_eq!(indices, vec![vec![0, 2], vec![1], vec![3, 5], vec![4]]);
        let c = config(false);
        let planned = plan::plan(&c);
        let runs: Vec<&RunSpec> = planned.iter().collect();
        assert_eq!(groups(&c, &runs).len(), 6);
    }
}
