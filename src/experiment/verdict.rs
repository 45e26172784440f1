//! The verdict a report opens with: per job, the fastest method and every other method's speed
//! against it, the wavefront's (and the slower megakernels') speed against the fastest
//! megakernel, and the error side by side; with a one-line caveat when the GPU methods ran on a
//! software driver, whose "GPU" times measure a CPU. Written as plain sentences so that
//! `report.html` and the Markdown results pages say the same thing ([`Verdict::lines`]); a
//! figure that is not steady carries [`FLAG`].

use std::collections::BTreeMap;

use super::baseline::{self, Baseline};
use super::report::{ExperimentReport, RunRecord, RunStatus};
use super::stability::{self, FLAG};

/// What a report found, job by job.
pub struct Verdict {
    /// The software-driver caveat, when a GPU run's adapter is one.
    pub caveat: Option<String>,
    /// One sentence group per job, in the order the report first ran each job: the first
    /// [`MAX_JOBS`] of them.
    pub jobs: Vec<JobVerdict>,
    /// Jobs left out beyond [`MAX_JOBS`] (a sweep of hundreds of jobs has no one-screen verdict;
    /// its tables hold every run).
    pub omitted: usize,
}

/// The most jobs a verdict names.
pub const MAX_JOBS: usize = 12;

/// One job's finding: its name and its sentences.
pub struct JobVerdict {
    /// `three-spheres 160×90, 4 spp, depth 50, NEE`.
    pub job: String,
    /// `fastest: cpu, 0.005500 s; …`, then the megakernel comparison and the error.
    pub sentences: Vec<String>,
}

impl Verdict {
    /// The report's verdict (no job without an ok, timed run).
    pub fn of(report: &ExperimentReport) -> Verdict {
        let threshold = stability::threshold_of(&report.config);
        let fastest_mk = baseline::fastest_megakernel(report);
        let mut jobs: Vec<(String, Vec<&RunRecord>)> = Vec::new();
        for r in &report.runs {
            let key = baseline::job_key(r);
            match jobs.iter_mut().find(|(k, _)| *k == key) {
                Some((_, runs)) => runs.push(r),
                None => jobs.push((key, vec![r])),
            }
        }
        let mut jobs: Vec<JobVerdict> = jobs
            .into_iter()
            .filter_map(|(key, runs)| job_verdict(&runs, fastest_mk.get(&key), threshold))
            .collect();
        let omitted = jobs.len().saturating_sub(MAX_JOBS);
        jobs.truncate(MAX_JOBS);
        Verdict { caveat: software_caveat(report), jobs, omitted }
    }

    /// The verdict as lines of text: the caveat, then `job: sentences` per job.
    pub fn lines(&self) -> Vec<String> {
        let mut out: Vec<String> = self.caveat.iter().cloned().collect();
        out.extend(self.jobs.iter().map(|j| format!("{}: {}", j.job, j.sentences.join(" "))));
        out.extend(self.omitted_line());
        out
    }

    /// `…and 7 more jobs: …`, where jobs were left out.
    pub fn omitted_line(&self) -> Option<String> {
        (self.omitted > 0)
            .then(|| format!("…and {} more jobs: the tables below have every run.", self.omitted))
    }
}

/// A timed, ok run of a job, as the verdict compares it.
struct Timed<'a> {
    run: &'a RunRecord,
    seconds: f64,
    flagged: bool,
}

fn job_verdict(runs: &[&RunRecord], mk: Option<&Baseline>, threshold: f64) -> Option<JobVerdict> {
    let mut timed: Vec<Timed> = runs
        .iter()
        .filter(|r| r.status == RunStatus::Ok)
        .filter_map(|r| {
            let seconds = r.seconds.filter(|t| *t > 0.0)?;
            Some(Timed { run: r, seconds, flagged: stability::of_run(r, threshold).flagged() })
        })
        .collect();
    let first = runs.first()?;
    if timed.is_empty() {
        return None;
    }
    timed.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    let best = &timed[0];
    let fastest =
        format!("fastest {} ({} s{})", best.run.label, sig(best.seconds), stability::flag(best.flagged));
    let others: Vec<String> = timed[1..]
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let flag = stability::flag(t.flagged || best.flagged);
            let its = if i == 0 { " its speed" } else { "" };
            format!("{} {:.2}×{flag}{its}", t.run.label, best.seconds / t.seconds)
        })
        .collect();
    let mut sentences = vec![if others.is_empty() {
        format!("{fastest}, the only method timed.")
    } else {
        format!("{fastest}; {}.", others.join(", "))
    }];
    sentences.extend(versus_megakernel(&timed, mk));
    let failed: Vec<&str> =
        runs.iter().filter(|r| r.status == RunStatus::Failed).map(|r| r.label.as_str()).collect();
    if !failed.is_empty() {
        sentences.push(format!("Failed: {}.", failed.join(", ")));
    }
    sentences.extend(error_sentence(&timed));
    Some(JobVerdict { job: job_name(first), sentences })
}

/// `wavefront 0.50× the fastest megakernel (megakernel)`: every GPU run but the fastest
/// megakernel itself, where the fastest run is not that megakernel (else the sentence before
/// already said it).
fn versus_megakernel(timed: &[Timed], mk: Option<&Baseline>) -> Option<String> {
    let mk = mk?;
    let baseline = timed.iter().find(|t| t.run.method == "megakernel" && t.seconds == mk.seconds)?;
    if std::ptr::eq(baseline, &timed[0]) {
        return None;
    }
    let against: Vec<String> = timed
        .iter()
        .filter(|t| t.run.method_needs_gpu() && !std::ptr::eq(*t, baseline))
        .map(|t| {
            let flag = stability::flag(t.flagged || mk.flagged);
            format!("{} {:.2}×{flag}", t.run.label, mk.seconds / t.seconds)
        })
        .collect();
    (!against.is_empty())
        .then(|| format!("Against the fastest megakernel ({}): {}.", baseline.run.label, against.join(", ")))
}

/// relMSE side by side: one figure when every method's rounds to the same, else each method's.
fn error_sentence(timed: &[Timed]) -> Option<String> {
    let mut by_config: Vec<&Timed> = timed.iter().collect();
    by_config.sort_by_key(|t| t.run.index);
    let errors: Vec<(&str, String)> = by_config
        .iter()
        .filter_map(|t| Some((t.run.label.as_str(), format!("{:.3e}", t.run.error_metrics.as_ref()?.relmse))))
        .collect();
    match errors.as_slice() {
        [] => None,
        [(label, e)] => Some(format!("relMSE: {label} {e}.")),
        [(_, e), rest @ ..] if rest.iter().all(|(_, x)| x == e) => {
            Some(format!("relMSE {e} for all {}.", errors.len()))
        }
        _ => {
            let each: Vec<String> = errors.iter().map(|(l, e)| format!("{l} {e}")).collect();
            Some(format!("relMSE: {}.", each.join(", ")))
        }
    }
}

/// `three-spheres 160×90, 4 spp, depth 50`, with NEE, roulette and the numerical knobs and
/// stress transform that set the job apart where not the default.
fn job_name(r: &RunRecord) -> String {
    let mut name = format!("{} {}×{}, {} spp, depth {}", r.scene, r.width, r.height, r.spp, r.max_depth);
    if r.nee {
        name.push_str(", NEE");
    }
    if r.roulette {
        name.push_str(", roulette");
    }
    let knobs: BTreeMap<&str, String> =
        ["ray_offset", "sphere_hit", "fresnel", "render_space", "scale", "translate"]
            .into_iter()
            .filter_map(|k| Some((k, r.options.get(k)?.to_string().trim_matches('"').to_string())))
            .collect();
    for (k, v) in knobs {
        if !matches!(
            (k, v.as_str()),
            ("scale", "1.0")
                | ("translate", "[0.0,0.0,0.0]")
                | ("ray_offset", "tmin")
                | ("sphere_hit", "stable")
                | ("fresnel", "schlick")
                | ("render_space", "camera")
        ) {
            name.push_str(&format!(", {k} {v}"));
        }
    }
    name
}

/// One line when a GPU run's adapter is a software driver (wgpu's device type `Cpu`).
fn software_caveat(report: &ExperimentReport) -> Option<String> {
    let software =
        report.runs.iter().filter(|r| r.method_needs_gpu() && r.status == RunStatus::Ok).find_map(|r| {
            let a = report.environments.get(r.environment)?.adapter.as_ref()?;
            let kind = a.get("device_type").and_then(|v| v.as_str());
            (kind == Some("Cpu"))
                .then(|| a.get("name").and_then(|v| v.as_str()).unwrap_or("a software driver").to_string())
        })?;
    let name = software.split(" (").next().unwrap_or(&software).to_string();
    Some(format!(
        "{FLAG} The GPU methods ran on {name}, a software driver: their times measure a CPU, not a GPU, \
         so compare them with each other, not with the CPU reference or a real GPU."
    ))
}

/// Four significant digits, as the results pages give seconds.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(
        index: usize,
        scene: &str,
        method: &str,
        label: &str,
        frames: &[f64],
        relmse: f64,
    ) -> serde_json::Value {
        let s = super::super::report::Stat::of(frames).unwrap();
        serde_json::json!({
            "index": index, "id": "x", "environment": 0, "scene": scene, "width": 2, "height": 2, "spp": 4,
            "max_depth": 5, "nee": false, "seed": 0, "accel": "bvh", "method": method,
            "label": label, "options": {}, "status": "ok", "warmup": 1,
            "repetitions": frames.len(), "samples": 16, "passes": {}, "passes_per_bounce": {},
            "frame_seconds": {"median": s.median, "min": s.min, "max": s.max, "values": s.values},
            "seconds": s.median, "error_metrics": {"mse": 1.0, "rmse": 1.0, "relmse": relmse, "smape": 0.1, "mape": 0.1, "flip": null,
                "non_finite_pixels": 0, "pixels": 4, "trimmed_pixels": 0, "trimmed_fraction": 0.0}
        })
    }

    fn report(runs: serde_json::Value, device_type: &str) -> ExperimentReport {
        serde_json::from_value(serde_json::json!({
            "schema": "wavetrace-experiment-report/1", "status": "complete", "name": "t",
            "question": "q", "config_file": "t.json", "config": {"unstable_spread": 0.1},
            "environments": [{"build": {}, "machine": {}, "started": "now",
                "adapter": {"name": "llvmpipe (LLVM 15)", "device_type": device_type}}],
            "runs_planned": 4, "runs_selected": 4, "missing_runs": [],
            "runs": runs, "references": [], "charts": []
        }))
        .unwrap()
    }

    /// The fastest run is named with its time; every other run's speed is against it, and the
    /// GPU runs are set against the fastest megakernel when that is not the fastest run; equal
    /// errors are said once; a software adapter gets the caveat.
    #[test]
    fn the_verdict_names_the_fastest_and_every_speed_against_it() {
        let r = report(
            serde_json::json!([
                run(0, "s", "cpu", "cpu", &[1.0, 1.0, 1.0], 0.5),
                run(1, "s", "megakernel", "megakernel", &[2.0, 2.0, 2.0], 0.5),
                run(2, "s", "megakernel", "mk-regen", &[4.0, 4.0, 4.0], 0.5),
                run(3, "s", "wavefront", "wavefront", &[2.5, 2.5, 2.5], 0.5),
            ]),
            "Cpu",
        );
        let v = Verdict::of(&r);
        assert!(
            v.caveat.as_deref().is_some_and(|c| c.contains("llvmpipe, a software driver")),
            "{:?}",
            v.caveat
        );
        let lines = v.lines();
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert_eq!(
            lines[1],
            "s 2×2, 4 spp, depth 5: fastest cpu (1.000 s); megakernel 0.50× its speed, wavefront 0.40×, \
             mk-regen 0.25×. Against the fastest megakernel (megakernel): wavefront 0.80×, mk-regen 0.50×. \
             relMSE 5.000e-1 for all 4."
        );
        assert!(Verdict::of(&report(serde_json::json!([]), "DiscreteGpu")).lines().is_empty());
        // A sweep of many jobs: the first MAX_JOBS, and how many more.
        let many: Vec<serde_json::Value> =
            (0..MAX_JOBS + 3).map(|i| run(i, &format!("s{i}"), "cpu", "cpu", &[1.0], 0.5)).collect();
        let v = Verdict::of(&report(serde_json::json!(many), "DiscreteGpu"));
        assert_eq!((v.jobs.len(), v.omitted), (MAX_JOBS, 3));
        assert_eq!(v.lines().last().unwrap(), "…and 3 more jobs: the tables below have every run.");
    }

    /// A real GPU gets no caveat; an unsteady time carries the flag into every ratio built on
    /// it; different errors are listed per method.
    #[test]
    fn unsteady_figures_are_flagged_and_errors_listed() {
        let r = report(
            serde_json::json!([
                run(0, "s", "megakernel", "megakernel", &[1.0, 1.5, 0.9], 0.5),
                run(1, "s", "wavefront", "wavefront", &[2.0, 2.0, 2.0], 0.25),
            ]),
            "DiscreteGpu",
        );
        let v = Verdict::of(&r);
        assert!(v.caveat.is_none());
        assert_eq!(
            v.lines()[0],
            format!(
                "s 2×2, 4 spp, depth 5: fastest megakernel (1.000 s{FLAG}); wavefront 0.50×{FLAG} its speed. \
                 relMSE: megakernel 5.000e-1, wavefront 2.500e-1."
            )
        );
    }
}
