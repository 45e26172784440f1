//! Tidy tables beside `report.json`: `runs.csv` (one row per run) and `passes.csv` (one row per
//! run × GPU pass), for pandas, R or a spreadsheet without walking the JSON. Derived from the
//! report alone and rewritten with it, so they never say more or less than it does.
//!
//! RFC 4180: a header row, CRLF line ends, fields holding `,` `"` CR or LF quoted with `"` doubled.
//! Missing values are empty cells; numbers are written as Rust prints them (shortest text that
//! reads back to the same f64, `.` as decimal point whatever the locale, `1e-7` for small ones).

use crate::gpu::instrument::FRAME_KEY;
use crate::gpu::memory::MemoryCategory;
use crate::gpu::timing::FRAME_LABEL;
use std::collections::BTreeSet;
use std::path::Path;

use anyhow::{Context, Result};
use serde_json::Value;

use super::report::{ExperimentReport, RunRecord, Stat};
use crate::image_io::write_file_atomically;

pub const RUNS_FILE: &str = "runs.csv";
pub const PASSES_FILE: &str = "passes.csv";

/// The knobs' columns come in config order ([`KNOBS`]); a knob a later build adds and that list
/// lacks still gets a column, after these, by name.
pub use crate::options::knobs::COLUMNS as KNOBS;

/// `ErrorMetrics`' fields, in the order their columns take (a unit test keeps this in step).
pub const METRICS: [&str; 10] = [
    "mse",
    "rmse",
    "relmse",
    "smape",
    "mape",
    "flip",
    "non_finite_pixels",
    "pixels",
    "trimmed_pixels",
    "trimmed_fraction",
];

/// Writes `runs.csv` and `passes.csv` into `dir`, each atomically.
pub fn write(report: &ExperimentReport, dir: &Path) -> Result<()> {
    for (file, text) in [(RUNS_FILE, runs_csv(report)), (PASSES_FILE, passes_csv(report))] {
        let path = dir.join(file);
        write_file_atomically(&path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

type Cell = Option<String>;
type Column<'a, T> = (String, Box<dyn Fn(&T) -> Cell + 'a>);
/// A run and one of its pass labels.
type PassRow<'a> = (&'a RunRecord, String);

/// `runs.csv`: one row per run, in the report's order.
pub fn runs_csv(report: &ExperimentReport) -> String {
    let cols = run_columns(report);
    table(&cols, report.runs.iter())
}

/// `passes.csv`: one row per run and pass label (and per SIMD-efficiency point that is no pass).
pub fn passes_csv(report: &ExperimentReport) -> String {
    let rows: Vec<PassRow> = report
        .runs
        .iter()
        .flat_map(|r| {
            let labels: BTreeSet<&String> =
                r.passes.keys().chain(r.simd.iter().flat_map(|s| s.keys())).collect();
            labels.into_iter().map(move |l| (r, l.clone()))
        })
        .collect();
    let pass = |(r, l): &PassRow| r.passes.get(l).cloned();
    // A pass's own time only where timestamps measured it; on the wall clock, only `frame` has one.
    let timed = move |x: &PassRow| {
        pass(x).filter(|_| x.0.time_source.as_deref() != Some("wall-clock") || x.1 == FRAME_LABEL)
    };
    let simd = |(r, l): &PassRow| r.simd.as_ref().and_then(|s| s.get(l)).cloned();
    let cols: Vec<Column<PassRow>> = vec![
        col::<PassRow>("run_index", |x| int(x.0.index)),
        col::<PassRow>("run_id", |x| text(&x.0.id)),
        col::<PassRow>("scene", |x| text(&x.0.scene)),
        col::<PassRow>("width", |x| int(x.0.width)),
        col::<PassRow>("height", |x| int(x.0.height)),
        col::<PassRow>("spp", |x| int(x.0.spp)),
        col::<PassRow>("method", |x| text(&x.0.method)),
        col::<PassRow>("label", |x| text(&x.0.label)),
        col::<PassRow>("pass", |x| text(&x.1)),
        col::<PassRow>("seconds_median", move |x| timed(x).map(|p| float(p.seconds.median))),
        col::<PassRow>("seconds_min", move |x| timed(x).map(|p| float(p.seconds.min))),
        col::<PassRow>("seconds_max", move |x| timed(x).map(|p| float(p.seconds.max))),
        col::<PassRow>("passes", move |x| pass(x).map(|p| p.passes.to_string())),
        // Of the run's summed median pass times, so a run's shares add up to 1.
        col::<PassRow>("share", move |x| {
            let total: f64 = x.0.passes.values().map(|p| p.seconds.median).sum();
            timed(x).filter(|_| total > 0.0).map(|p| float(p.seconds.median / total))
        }),
        col::<PassRow>("simd_efficiency", move |x| simd(x).map(|s| float(s.efficiency))),
        col::<PassRow>("simd_subgroups", move |x| simd(x).map(|s| s.subgroups.to_string())),
    ];
    table(&cols, rows.iter())
}

fn run_columns(report: &ExperimentReport) -> Vec<Column<'static, RunRecord>> {
    let mut cols = setting_columns();
    cols.extend(knob_columns(report));
    cols.extend(time_and_count_columns());
    cols.extend(memory_columns());
    cols.push(rcol("indirect_validation", |r| r.indirect_validation.and_then(flag)));
    cols.extend(error_and_image_columns());
    cols.extend(steadiness_and_cost_columns(report));
    cols.extend(gpu_state_columns());
    cols
}

/// The run's render settings and method.
fn setting_columns() -> Vec<Column<'static, RunRecord>> {
    vec![
        rcol("index", |r| int(r.index)),
        rcol("id", |r| text(&r.id)),
        rcol("scene", |r| text(&r.scene)),
        rcol("width", |r| int(r.width)),
        rcol("height", |r| int(r.height)),
        rcol("spp", |r| int(r.spp)),
        rcol("max_depth", |r| int(r.max_depth)),
        rcol("nee", |r| flag(r.nee)),
        rcol("roulette", |r| flag(r.roulette)),
        rcol("seed", |r| int(r.seed)),
        rcol("accel", |r| text(&r.accel)),
        rcol("method", |r| text(&r.method)),
        rcol("label", |r| text(&r.label)),
    ]
}

/// One column per option knob: the known ones in order, then any other a run's options hold.
fn knob_columns(report: &ExperimentReport) -> Vec<Column<'static, RunRecord>> {
    let mut knobs: Vec<String> = KNOBS.iter().map(|k| k.to_string()).collect();
    let extra: BTreeSet<&String> = report
        .runs
        .iter()
        .filter_map(|r| r.options.as_object())
        .flat_map(|o| o.keys())
        .filter(|k| !KNOBS.contains(&k.as_str()))
        .collect();
    knobs.extend(extra.into_iter().cloned());

    let mut cols: Vec<Column<'static, RunRecord>> = Vec::new();
    for k in knobs {
        cols.push((k.clone(), Box::new(move |r: &RunRecord| r.options.get(&k).and_then(json))));
    }
    cols
}

/// Outcome, times, throughput and counts.
fn time_and_count_columns() -> Vec<Column<'static, RunRecord>> {
    // The stat `seconds` is the median of (`RunRecord::timed_stat`): frame time where measured
    // (GPU time in reports written before it), else wall time.
    let timed = |r: &RunRecord| r.timed_stat().cloned();
    let stat = |f: fn(&Stat) -> f64, s: Option<Stat>| s.map(|s| float(f(&s)));
    vec![
        rcol("status", |r| serde_json::to_value(r.status).ok().as_ref().and_then(json)),
        rcol("error", |r| r.error.clone()),
        rcol("resumed", |r| flag(r.resumed)),
        rcol("environment", |r| int(r.environment)),
        rcol("warmup", |r| int(r.warmup)),
        rcol("repetitions", |r| int(r.repetitions)),
        rcol("time_source", |r| r.time_source.clone()),
        rcol("seconds", |r| r.seconds.map(float)),
        rcol("seconds_min", move |r| stat(|s| s.min, timed(r))),
        rcol("seconds_max", move |r| stat(|s| s.max, timed(r))),
        rcol("wall_seconds_median", move |r| stat(|s| s.median, r.wall_seconds.clone())),
        rcol("wall_seconds_min", move |r| stat(|s| s.min, r.wall_seconds.clone())),
        rcol("wall_seconds_max", move |r| stat(|s| s.max, r.wall_seconds.clone())),
        rcol("gpu_seconds_median", move |r| stat(|s| s.median, r.gpu_seconds.clone())),
        rcol("gpu_seconds_min", move |r| stat(|s| s.min, r.gpu_seconds.clone())),
        rcol("gpu_seconds_max", move |r| stat(|s| s.max, r.gpu_seconds.clone())),
        rcol("frame_seconds_median", move |r| stat(|s| s.median, r.frame_seconds.clone())),
        rcol("frame_seconds_min", move |r| stat(|s| s.min, r.frame_seconds.clone())),
        rcol("frame_seconds_max", move |r| stat(|s| s.max, r.frame_seconds.clone())),
        rcol("host_gap_seconds", |r| r.host_gap_seconds.map(float)),
        rcol("between_passes_seconds", |r| r.between_passes_seconds.map(float)),
        rcol("profiled_frame_seconds", |r| r.profiled_frame_seconds.map(float)),
        rcol("samples", |r| int(r.samples)),
        rcol("samples_per_second", |r| r.samples_per_second.map(float)),
        rcol("rays", |r| r.rays.and_then(int)),
        rcol("rays_per_second", |r| r.rays_per_second.map(float)),
        rcol("dispatches", |r| r.dispatches.and_then(int)),
        rcol("empty_dispatches", |r| r.empty_dispatches.and_then(int)),
        rcol("iterations", |r| r.iterations.and_then(int)),
        rcol("idle_iterations", |r| r.idle_iterations.and_then(int)),
        rcol("intersect_occupancy", |r| r.intersect_occupancy.map(float)),
        rcol("state_bytes_per_sample", |r| r.state_traffic.as_ref().map(|t| float(t.bytes_per_sample))),
        // Instrumented runs only: the work-weighted frame figure (nvprof's counterpart).
        rcol(FRAME_KEY, |r| r.simd.as_ref().and_then(|s| s.get(FRAME_KEY)).map(|e| float(e.efficiency))),
        rcol("invalid_samples", |r| r.invalid_samples.and_then(int)),
        rcol("self_hits", |r| r.self_hits.and_then(int)),
        rcol("shadow_self_hits", |r| r.shadow_self_hits.and_then(int)),
        rcol("depth_cut", |r| r.depth_cut.and_then(int)),
        rcol("image_mean", |r| r.image_mean.map(float)),
        rcol("repeatable", |r| r.repeatable.and_then(flag)),
        rcol("bytes_per_path", |r| r.bytes_per_path.and_then(int)),
        // The record's `pool_size` is the pool used; the knob column `pool_size` is the setting.
        rcol("pool_size_used", |r| r.pool_size.and_then(int)),
    ]
}

/// GPU memory: one column per category (empty where a method has none), the total and peak.
fn memory_columns() -> Vec<Column<'static, RunRecord>> {
    let mut cols: Vec<Column<'static, RunRecord>> = Vec::new();
    for category in MemoryCategory::ALL {
        cols.push(rcol(&format!("memory_{}", category.key()), move |r| {
            r.memory.as_ref().and_then(|m| m.by_category.get(category.key())).and_then(int)
        }));
    }
    cols.extend([
        rcol("memory_total", |r| r.memory.as_ref().and_then(|m| int(m.total))),
        rcol("memory_peak", |r| r.memory.as_ref().and_then(|m| int(m.peak))),
    ]);
    cols
}

/// The error against the reference and the image files.
fn error_and_image_columns() -> Vec<Column<'static, RunRecord>> {
    let mut cols = vec![rcol("reference", |r| r.reference.clone())];
    let metric = |name: &'static str| {
        move |r: &RunRecord| {
            r.error_metrics.as_ref().and_then(|m| serde_json::to_value(m).ok()?.get(name).and_then(json))
        }
    };
    for name in METRICS {
        cols.push((name.to_string(), Box::new(metric(name))));
    }
    cols.extend([
        rcol("efficiency", |r| r.efficiency.map(float)),
        rcol("exr", |r| r.images.as_ref().map(|i| i.exr.clone())),
        rcol("png", |r| r.images.as_ref().map(|i| i.png.clone())),
        rcol("error_map", |r| r.images.as_ref().and_then(|i| i.error_map.clone())),
    ]);
    cols
}

/// Whether the time is a steady figure (stored, or computed from the repetitions for reports
/// from before it was), how the run warmed up, and what it cost (passes, scene, BVH, traversal).
fn steadiness_and_cost_columns(report: &ExperimentReport) -> Vec<Column<'static, RunRecord>> {
    let mut cols: Vec<Column<'static, RunRecord>> = Vec::new();
    let threshold = super::stability::threshold_of(&report.config);
    let steady = move |r: &RunRecord| super::stability::of_run(r, threshold);
    cols.extend([
        rcol("spread", move |r| steady(r).spread.map(float)),
        rcol("median_low", move |r| steady(r).median_low.map(float)),
        rcol("median_high", move |r| steady(r).median_high.map(float)),
        rcol("median_confidence", move |r| steady(r).confidence.map(float)),
        rcol("unstable", move |r| flag(steady(r).unstable)),
        rcol("cold", move |r| flag(steady(r).cold)),
        rcol("warmup_policy", |r| r.warmup_log.as_ref().map(|w| w.policy.clone())),
        rcol("warmup_seconds", |r| r.warmup_log.as_ref().map(|w| float(w.seconds))),
        rcol("warmup_settled", |r| r.warmup_log.as_ref().and_then(|w| flag(w.settled))),
        rcol("compute_passes_used", |r| r.compute_passes.and_then(int)),
        rcol("submissions", |r| r.submissions.and_then(int)),
        rcol("waits", |r| r.waits.and_then(int)),
        rcol("blocking_reads", |r| r.blocking_reads.and_then(int)),
        rcol("speculative_iterations", |r| r.speculative_iterations.and_then(int)),
        rcol("preheat_seconds", |r| r.preheat_seconds.map(float)),
        rcol("scene_prepare_seconds", |r| r.scene_prepare_seconds.map(float)),
        rcol("bvh_nodes", |r| r.bvh.as_ref().and_then(|b| int(b.nodes))),
        rcol("bvh_bytes", |r| r.bvh.as_ref().and_then(|b| int(b.bytes))),
        rcol("bvh_depth", |r| r.bvh.as_ref().and_then(|b| int(b.depth as u64))),
        rcol("bvh_build_seconds", |r| r.bvh_build_seconds.map(float)),
        rcol("bvh_bytes_per_ray", |r| r.traversal.map(|t| float(t.all.bvh_bytes))),
        rcol("node_fetches_per_ray", |r| r.traversal.map(|t| float(t.all.node_fetches))),
        rcol("primitive_tests_per_ray", |r| r.traversal.map(|t| float(t.all.primitive_tests))),
        rcol("traversal_iterations_per_ray", |r| r.traversal.map(|t| float(t.all.iterations))),
        rcol("deepest_stack", |r| r.traversal.and_then(|t| int(t.all.deepest_stack))),
        rcol("interleaved_with", |r| {
            Some(r.interleaved_with.iter().map(usize::to_string).collect::<Vec<_>>().join(" "))
        }),
    ]);
    cols
}

/// The GPU's state (clocks, temperature, power, throttling) before and after the timed renders.
fn gpu_state_columns() -> Vec<Column<'static, RunRecord>> {
    let mut cols: Vec<Column<'static, RunRecord>> = Vec::new();
    type Reading = fn(&crate::gpu::state::GpuState) -> Cell;
    let readings: [(&str, Reading); 5] = [
        ("sm_clock_mhz", |g| g.sm_clock_mhz.and_then(int)),
        ("memory_clock_mhz", |g| g.memory_clock_mhz.and_then(int)),
        ("temperature_c", |g| g.temperature_c.and_then(int)),
        ("power_watts", |g| g.power_watts.map(float)),
        ("throttle_reasons", |g| g.throttle_reasons.as_ref().map(|v| v.join(" "))),
    ];
    for (name, read) in readings {
        cols.push(rcol(&format!("{name}_before"), move |r| {
            r.gpu_state.as_ref().and_then(|g| read(&g.before))
        }));
        cols.push(rcol(&format!("{name}_after"), move |r| r.gpu_state.as_ref().and_then(|g| read(&g.after))));
    }
    cols
}

/// A column of `runs.csv` (a plain `fn`, so closures learn their argument's type).
fn rcol(name: &str, f: impl Fn(&RunRecord) -> Cell + 'static) -> Column<'static, RunRecord> {
    col(name, f)
}

fn col<'a, T>(name: &str, f: impl Fn(&T) -> Cell + 'a) -> Column<'a, T> {
    (name.to_string(), Box::new(f))
}

fn int(v: impl std::fmt::Display) -> Cell {
    Some(v.to_string())
}

/// Shortest round-trip text (`0.1`, `3.0`, `1e-7`), never a locale's.
fn float(v: f64) -> String {
    format!("{v:?}")
}

fn text(s: &str) -> Cell {
    Some(s.to_string())
}

fn flag(b: bool) -> Cell {
    Some(b.to_string())
}

/// A JSON value as a cell: null empty, strings bare, anything else as JSON text.
fn json(v: &Value) -> Cell {
    match v {
        Value::Null => None,
        Value::String(s) => Some(s.clone()),
        other => Some(other.to_string()),
    }
}

fn table<'r, T: 'r>(cols: &[Column<T>], rows: impl Iterator<Item = &'r T>) -> String {
    let mut out = String::new();
    line(&mut out, cols.iter().map(|(name, _)| name.as_str()));
    for row in rows {
        let cells: Vec<Cell> = cols.iter().map(|(_, f)| f(row)).collect();
        line(&mut out, cells.iter().map(|c| c.as_deref().unwrap_or("")));
    }
    out
}

fn line<'a>(out: &mut String, fields: impl Iterator<Item = &'a str>) {
    for (i, f) in fields.enumerate() {
        if i > 0 {
            out.push(',');
        }
        out.push_str(&quote(f));
    }
    out.push_str("\r\n");
}

/// RFC 4180 §2.6–2.7: quote a field holding a separator, quote or line break; double its quotes.
pub fn quote(field: &str) -> std::borrow::Cow<'_, str> {
    if field.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\"")).into()
    } else {
        field.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_quoted_as_rfc_4180_says() {
        assert_eq!(quote("plain"), "plain");
        assert_eq!(quote("a,b"), "\"a,b\"");
        assert_eq!(quote("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(quote("two\nlines"), "\"two\nlines\"");
        assert_eq!(quote(""), "");
    }

    #[test]
    fn numbers_read_back_exactly() {
        for v in [0.1, 3.0, 1e-7, 123456.789, 2.5e20, f64::MIN_POSITIVE] {
            assert_eq!(float(v).parse::<f64>().unwrap(), v, "{}", float(v));
        }
        assert_eq!(float(3.0), "3.0");
    }

    #[test]
    fn metric_columns_are_every_error_metric() {
        let img = crate::image_io::RgbImage { width: 2, height: 1, data: vec![0.5; 6] };
        let m = crate::metrics::compare(&img, &img, &crate::metrics::CompareOptions::default()).unwrap();
        let v = serde_json::to_value(m).unwrap();
        let fields: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(fields, METRICS);
    }
}
