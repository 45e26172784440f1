//! `report.json` (`"schema": "wavetrace-experiment-report/1"`): everything an experiment measured,
//! with where and from what code, so each figure can be traced to its run. The schema is
//! documented in the README and as JSON Schema in `experiments/report.schema.json`; a test checks
//! real reports against it. Written atomically after every run, so a killed experiment leaves the
//! last complete report, which `experiment run --resume` continues (`resume.rs`).

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::plan::Shard;
use crate::gpu::instrument::SimdEfficiency;
use crate::gpu::memory::GpuMemory;
use crate::gpu::wavefront::QueueHistogram;
use crate::metrics::ErrorMetrics;

pub const REPORT_SCHEMA: &str = "wavetrace-experiment-report/1";
pub const REPORT_FILE: &str = "report.json";

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ReportStatus {
    /// Runs are still going (or the process was killed): `runs` holds the finished ones.
    Running,
    /// Every selected run finished (succeeded or failed).
    Complete,
    /// A merge that lacks some of the config's runs (`missing_runs` lists them).
    Incomplete,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ExperimentReport {
    pub schema: String,
    pub status: ReportStatus,
    /// The config file's stem.
    pub name: String,
    pub question: String,
    pub config_file: String,
    /// The config as written.
    pub config: Value,
    /// The `--set KEY=VALUE` overrides applied to the config file, as given (`config` holds the
    /// result). Absent when there were none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
    /// Where runs ran: one entry per process (several after a merge of shards).
    pub environments: Vec<Environment>,
    /// Runs in the whole config.
    pub runs_planned: usize,
    /// Runs this report set out to do (a shard's share; all for a merge).
    pub runs_selected: usize,
    /// Indices of planned runs absent from `runs` (merges only; empty otherwise).
    pub missing_runs: Vec<usize>,
    pub runs: Vec<RunRecord>,
    pub references: Vec<ReferenceRecord>,
    /// Chart files under `charts/`.
    pub charts: Vec<ChartRecord>,
}

/// One process's machine, adapter and build.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Environment {
    pub shard: Option<Shard>,
    /// crate version, git commit (`-dirty` when built from a modified tree) and the executable's
    /// digest (what `--resume` compares when the commit cannot tell).
    pub build: Value,
    /// hostname, OS, CPU, logical cores.
    pub machine: Value,
    /// The GPU adapter (name, backend, driver, limits); null when no GPU run started.
    pub adapter: Option<Value>,
    /// RFC 3339 UTC.
    pub started: String,
    /// None while running, or when the process was killed.
    pub finished: Option<String>,
    /// Set when this process resumed an earlier attempt (`experiment run --resume`).
    #[serde(default)]
    pub resume: Option<ResumeRecord>,
    /// Where the GPU's clocks and temperature were read (`NVML: <device name>`); None where they
    /// could not be (no NVIDIA driver, another vendor, or no GPU run).
    #[serde(default)]
    pub gpu_state_source: Option<String>,
}

/// What a resuming process took over from the attempt before it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResumeRecord {
    /// Plan indices of the runs kept as they were (their records say `resumed: true`).
    pub kept: Vec<usize>,
    /// Runs that had failed in the earlier attempt and were run again, with their old error.
    pub retried: Vec<RetriedRun>,
    /// `--allow-other-build`: kept runs come from a build that could not be shown to be this one.
    pub other_build: bool,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RetriedRun {
    pub index: usize,
    pub id: String,
    pub error: Option<String>,
}

impl Environment {
    /// This process: its build (with the executable's digest), machine and start time.
    pub fn this(shard: Option<Shard>) -> Result<Self> {
        let mut build = serde_json::to_value(crate::report::Build::this())?;
        if let (Some(digest), Some(map)) = (executable_digest(), build.as_object_mut()) {
            map.insert("executable_digest".into(), Value::String(digest));
        }
        Ok(Self {
            shard,
            build,
            machine: serde_json::to_value(crate::report::Machine::this())?,
            adapter: None,
            started: now_rfc3339(),
            finished: None,
            resume: None,
            gpu_state_source: None,
        })
    }
}

/// 64-bit FNV-1a of the running executable, `fnv1a64:HEX`, computed once per process: the
/// build identity `--resume` trusts when the git commit cannot vouch for the code.
pub fn executable_digest() -> Option<String> {
    static DIGEST: OnceLock<Option<String>> = OnceLock::new();
    DIGEST
        .get_or_init(|| {
            // /proc/self/exe is the running file even after a rebuild replaced it on disk.
            let path = if cfg!(target_os = "linux") {
                std::path::PathBuf::from("/proc/self/exe")
            } else {
                std::env::current_exe().ok()?
            };
            let mut file = std::fs::File::open(path).ok()?;
            let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
            let mut buf = vec![0u8; 1 << 20];
            loop {
                let n = file.read(&mut buf).ok()?;
                if n == 0 {
                    break;
                }
                for &b in &buf[..n] {
                    hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
                }
            }
            Some(format!("fnv1a64:{hash:016x}"))
        })
        .clone()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    Ok,
    Failed,
}

/// How steady a run's time is. Stored in each run of `report.json`; pages recompute it from the
/// repetitions for reports written before it existed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stability {
    /// (max − min) / median over the timed repetitions of the run's time (frame time for GPU
    /// methods, wall time for CPU methods); None with one repetition.
    pub spread: Option<f64>,
    /// An interval holding the population median with probability `confidence`, from the order
    /// statistics of the repetitions (no assumption on their distribution); None with one.
    pub median_low: Option<f64>,
    pub median_high: Option<f64>,
    pub confidence: Option<f64>,
    /// The spread above which the run counts as unstable (the config's `unstable_spread`).
    pub threshold: f64,
    /// `spread > threshold`.
    pub unstable: bool,
    /// A GPU method timed without any warm-up render.
    pub cold: bool,
}

impl Stability {
    /// Unstable or cold: its times are not steady figures.
    pub fn flagged(&self) -> bool {
        self.unstable || self.cold
    }

    /// A short reason for pages: `unstable: 46% spread`, `cold: no warm-up`, both, or empty.
    pub fn reason(&self) -> String {
        let mut why = Vec::new();
        if self.unstable {
            why.push(format!("unstable: {:.0}% spread", 100.0 * self.spread.unwrap_or(0.0)));
        }
        if self.cold {
            why.push("cold: no warm-up".to_string());
        }
        why.join("; ")
    }

    /// The interval of the median, or (median, median) where there is none.
    pub fn interval_or(&self, median: f64) -> (f64, f64) {
        (self.median_low.unwrap_or(median), self.median_high.unwrap_or(median))
    }
}

/// Median, min and max over the timed repetitions, and the values themselves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stat {
    pub median: f64,
    pub min: f64,
    pub max: f64,
    pub values: Vec<f64>,
}

impl Stat {
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        let median = crate::stats::median_of_sorted(&v);
        Some(Self { median, min: v[0], max: v[v.len() - 1], values: values.to_vec() })
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassStat {
    /// GPU seconds of this label per render (over repetitions).
    pub seconds: Stat,
    /// Passes with this label per render.
    pub passes: u64,
}

/// Output files of a run, relative to the report's directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunImages {
    pub exr: String,
    pub png: String,
    /// False-colour relative error against the reference (None without a reference).
    pub error_map: Option<String>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    pub index: usize,
    pub id: String,
    /// Index into `environments`.
    pub environment: usize,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub max_depth: u32,
    /// Next-event estimation on (absent in reports from before it existed: off).
    #[serde(default)]
    pub nee: bool,
    /// Russian roulette on, pbrt-v4's rule (absent in reports from before it existed: off).
    #[serde(default)]
    pub roulette: bool,
    pub seed: u32,
    pub accel: String,
    pub method: String,
    /// The method variant's label (method name plus the knobs that tell variants apart).
    pub label: String,
    /// The knobs in force.
    pub options: Value,
    pub status: RunStatus,
    /// Kept from an earlier, interrupted attempt by `--resume` instead of rendered by the process
    /// that resumed (`environment` says which process rendered it).
    #[serde(default)]
    pub resumed: bool,
    /// Why the run failed (status `failed`).
    pub error: Option<String>,
    /// Warm-up renders done before the timed ones (reports from before timed warm-ups: the
    /// number the config asked for); `warmup_log` says how and how warm.
    pub warmup: u32,
    pub repetitions: u32,
    /// The warm-up's policy, frames, seconds, whether it settled, and each frame's time (and
    /// the GPU's state where NVML reads it). Absent in reports from before timed warm-ups.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warmup_log: Option<crate::warmup::WarmupLog>,
    /// Plan indices of the runs whose timed repetitions took turns with this one's (the GPU
    /// variants of the same job, `interleave`); empty when it ran its repetitions alone.
    #[serde(default)]
    pub interleaved_with: Vec<usize>,
    /// The spread of the timed repetitions, an interval for their median, and the flags
    /// (unstable, cold) that say whether its times are steady figures (absent in reports from
    /// before it existed: pages compute it from the repetitions).
    #[serde(default)]
    pub stability: Option<Stability>,
    /// The GPU's clocks, temperature, power and throttle reasons before the first timed render
    /// and after the last (NVIDIA through NVML only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_state: Option<crate::gpu::state::GpuStateSpan>,
    /// Host time per render (GPU methods: scene upload and pipeline creation included).
    pub wall_seconds: Option<Stat>,
    /// Sum of GPU pass times per render (GPU methods).
    pub gpu_seconds: Option<Stat>,
    /// Wall clock from a render's first submission to its last completion (GPU methods): GPU
    /// work plus the GPU's idle time while the host reads back and decides.
    #[serde(default)]
    pub frame_seconds: Option<Stat>,
    /// Median over repetitions of the frame's host gaps: the GPU idle between a submission's
    /// completion and the next submission, while the host reads back and records.
    #[serde(default)]
    pub host_gap_seconds: Option<f64>,
    /// Submissions per frame (of the median repetition; GPU methods; absent in reports from
    /// before). Reports without `waits` waited for each one; since, `waits` counts the waits.
    #[serde(default)]
    pub submissions: Option<u64>,
    /// Host seconds to prepare the scene for a render (move into render space, packing, the BVH
    /// build above all), median over the timed repetitions; not part of any time above. Absent in
    /// reports from before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_prepare_seconds: Option<f64>,
    /// The BVH traversed: layout, nodes, bytes, depth (absent in reports from before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bvh: Option<crate::bvh::BvhSummary>,
    /// Host seconds of the BVH's build, median over the timed repetitions (part of
    /// `scene_prepare_seconds`; absent in reports from before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bvh_build_seconds: Option<f64>,
    /// Times the host waited for the GPU per frame (of the median repetition): all but the last
    /// are blocking waits inside the frame (GPU methods; absent in reports from before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub waits: Option<u64>,
    /// Wavefront (median repetition): read-backs inside a share's loop the host waited for with
    /// no newer batch queued, the GPU idle (0 unless passes are timed). Absent before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blocking_reads: Option<u64>,
    /// Regenerating wavefront (median repetition): iterations recorded past a share's end (zero
    /// workgroups; not in `iterations`). Absent in reports from before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speculative_iterations: Option<u64>,
    /// Seconds of busy GPU work before each frame (`preheat_seconds` in the config; the median
    /// repetition's; 0 on a software adapter). Absent in reports written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preheat_seconds: Option<f64>,
    /// Median frame − median GPU time − host gaps: the GPU's time between its timed passes
    /// (launches, barriers), with per-pass timestamps only.
    #[serde(default)]
    pub between_passes_seconds: Option<f64>,
    /// The frame time of the one repetition run with per-pass timestamps, for the per-pass
    /// table, after the timed ones without them; beside `frame_seconds` it shows what the
    /// timestamps cost on this adapter (GPU methods with `timing: passes` and timestamps).
    #[serde(default)]
    pub profiled_frame_seconds: Option<f64>,
    /// `timestamps` or `wall-clock` (GPU methods).
    pub time_source: Option<String>,
    /// The time samples/s, rays/s and efficiency use: median frame time (GPU methods; reports
    /// written before it existed used the median GPU time), else median wall time.
    pub seconds: Option<f64>,
    pub passes: BTreeMap<String, PassStat>,
    /// Seconds per bounce of per-bounce passes, from the repetition with the median GPU time.
    pub passes_per_bounce: BTreeMap<String, Vec<f64>>,
    /// Paths per queue per bounce (wavefront with compaction).
    pub queue_histogram: Option<QueueHistogram>,
    /// Compute passes dispatched per render, empty ones included.
    pub dispatches: Option<u64>,
    /// Indirect dispatches the GPU sized to zero workgroups (their fixed cost bought nothing).
    #[serde(default)]
    pub empty_dispatches: Option<u64>,
    /// Compute passes the dispatches were recorded in (`dispatches` unless the wavefront's
    /// dispatches share passes: `compute_passes: shared`; absent in reports from before it).
    #[serde(default)]
    pub compute_passes: Option<u64>,
    /// Wavefront: iterations recorded (bounces × waves, or refill rounds when regenerating).
    #[serde(default)]
    pub iterations: Option<u64>,
    /// Wavefront: iterations that found no ray to trace.
    #[serde(default)]
    pub idle_iterations: Option<u64>,
    /// Wavefront: mean over intersect passes of the paths traced ÷ the pool.
    #[serde(default)]
    pub intersect_occupancy: Option<f64>,
    /// Wavefront with compaction: bytes of path state its passes read and wrote, modelled from
    /// the queue counts (`gpu::wavefront::traffic`), per sample and per pass.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_traffic: Option<crate::gpu::wavefront::traffic::StateTraffic>,
    pub samples: u64,
    pub samples_per_second: Option<f64>,
    pub rays: Option<u64>,
    pub rays_per_second: Option<f64>,
    /// NaN/Inf samples dropped.
    pub invalid_samples: Option<u64>,
    /// Secondary rays whose closest hit was the primitive they left (`numerics::Failures`), of
    /// the repetition with the median time, as `invalid_samples` (absent in reports from before
    /// they were counted).
    #[serde(default)]
    pub self_hits: Option<u64>,
    /// Shadow rays whose occluder was the primitive they left.
    #[serde(default)]
    pub shadow_self_hits: Option<u64>,
    /// Paths still going when they reached `max_depth`: cut, their remaining light lost.
    #[serde(default)]
    pub depth_cut: Option<u64>,
    pub image_mean: Option<f64>,
    /// Every repetition gave a bit-identical image (the counter-based RNG makes this expected).
    pub repeatable: Option<bool>,
    pub bytes_per_path: Option<u64>,
    /// GPU memory the render allocated, by category, and the peak (GPU methods).
    #[serde(default)]
    pub memory: Option<GpuMemory>,
    pub pool_size: Option<u32>,
    pub indirect_validation: Option<bool>,
    /// SIMD efficiency per pass or point, from a separate instrumented render (`instrument`).
    pub simd: Option<BTreeMap<String, SimdEfficiency>>,
    /// The wavefront intersect pass's coherence counters per iteration bucket, from the same
    /// instrumented render (issue 26; absent from reports made before them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coherence: Option<Vec<crate::gpu::instrument::Coherence>>,
    /// Traversal counts per ray on the CPU twin's paths (`instrument`, every method; issue 59;
    /// absent from reports made before them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traversal: Option<crate::cpu::traversal_counts::TraversalCounts>,
    /// Key of the reference in `references`.
    pub reference: Option<String>,
    pub error_metrics: Option<ErrorMetrics>,
    /// 1 / (relMSE · seconds), pbr-book's efficiency of a Monte Carlo estimator.
    pub efficiency: Option<f64>,
    pub images: Option<RunImages>,
}

impl RunRecord {
    /// The repetitions of the run's time: frame times for GPU methods (the sum of pass times in
    /// reports from before frame times), wall times for CPU methods.
    pub fn timed_stat(&self) -> Option<&Stat> {
        self.frame_seconds
            .as_ref()
            .or(self.gpu_seconds.as_ref())
            .filter(|g| g.median > 0.0)
            .or(self.wall_seconds.as_ref())
    }

    /// A GPU method's run.
    pub fn method_needs_gpu(&self) -> bool {
        self.method == "megakernel" || self.method == "wavefront"
    }
}

/// A reference image the runs were measured against.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ReferenceRecord {
    /// `scene-WxH-…-hash`: unique per scene, size and how it was made.
    pub key: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// `render` or `exr`.
    pub kind: String,
    pub method: Option<String>,
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub seed: Option<u32>,
    /// Next-event estimation on (rendered references).
    #[serde(default)]
    pub nee: Option<bool>,
    /// Russian roulette on (rendered references; absent in reports from before it existed).
    #[serde(default)]
    pub roulette: Option<bool>,
    /// The knobs it was rendered with, as the config spells them: `ray_offset`, `sphere_hit`,
    /// `fresnel`, `light_sampling`, `light_select` (EXR references: those the file's attributes
    /// name; None when it names none, and in reports from before the knobs existed).
    #[serde(default)]
    pub options: Option<Value>,
    /// Rendered for `"spp": "match"`: at its run's own spp, seed, depth, NEE, roulette and light
    /// knobs.
    #[serde(default)]
    pub spp_match: bool,
    /// The EXR: in the cache (rendered) or as configured.
    pub exr: String,
    /// Taken from the cache instead of rendered now.
    pub cached: bool,
    /// Seconds spent rendering it (0 when cached or read).
    pub render_seconds: f64,
    /// The commit that rendered it (from the EXR's `wavetrace.git_commit`), when known.
    pub git_commit: Option<String>,
    /// sRGB preview, relative to the report's directory.
    pub png: Option<String>,
    /// The EXR itself inside the report's directory (`references/KEY.exr`: a hard link to `exr`
    /// where the filesystem allows, else a copy), so the directory holds everything its runs
    /// were measured against. Absent in reports from before it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exr_copy: Option<String>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ChartRecord {
    /// `charts/NAME.svg`, relative to the report's directory.
    pub file: String,
    pub title: String,
    /// `error-vs-time`, `error-vs-spp`, `passes`, `queues`, `simd`, `speed-vs-memory`,
    /// `stability`, `warmup`, `time-by-scene` or `crossover`.
    pub kind: String,
    /// Empty for `time-by-scene`, which spans scenes.
    pub scene: String,
    /// 0 for `crossover`, which spans job sizes.
    pub width: u32,
    pub height: u32,
}

impl ExperimentReport {
    /// Reads `DIR/report.json`.
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(REPORT_FILE);
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
        let value: Value =
            serde_json::from_str(&text).with_context(|| format!("{}: malformed JSON", path.display()))?;
        match value.get("schema").and_then(Value::as_str) {
            Some(REPORT_SCHEMA) => {}
            Some(other) => bail!("{}: schema {other:?}; this build reads {REPORT_SCHEMA:?}", path.display()),
            None => bail!("{}: not an experiment report (no \"schema\" field)", path.display()),
        }
        serde_json::from_value(value)
            .with_context(|| format!("{}: not a valid experiment report", path.display()))
    }
}

/// Now, as RFC 3339 UTC to the second.
pub fn now_rfc3339() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    rfc3339(secs)
}

/// Unix seconds as RFC 3339 UTC (Howard Hinnant's civil-from-days).
pub fn rfc3339(unix: u64) -> String {
    let days = (unix / 86_400) as i64;
    let rem = unix % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rfc3339_matches_known_dates() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00Z");
        assert_eq!(rfc3339(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(rfc3339(1_795_358_261), "2026-11-22T14:37:41Z");
    }

    #[test]
    fn median_of_even_and_odd_counts() {
        assert_eq!(Stat::of(&[3.0, 1.0, 2.0]).unwrap().median, 2.0);
        let s = Stat::of(&[4.0, 1.0, 2.0, 3.0]).unwrap();
        assert_eq!((s.median, s.min, s.max), (2.5, 1.0, 4.0));
        assert_eq!(s.values, vec![4.0, 1.0, 2.0, 3.0]);
        assert!(Stat::of(&[]).is_none());
    }
}
