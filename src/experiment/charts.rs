//! The report's charts, one set per (scene, resolution): error against time (the speed-vs-accuracy
//! chart) and against spp (where f32 stops converging), GPU time per pass stacked per run, queue
//! occupancy per bounce, SIMD efficiency per pass where it was measured, and, where runs differ in
//! a stress transform (`scale`, `translate`), error and self-hits against it (`stability`); and,
//! where a config sweeps scenes, time by scene. Drawn from `report.json` alone, so `experiment
//! report` and `experiment merge` can re-draw them.

use std::collections::{BTreeMap, BTreeSet};

use serde_json::Value;

use super::baseline;
use super::method_colours::MethodColours;
use super::plan::file_safe;
use super::report::{ExperimentReport, RunRecord, RunStatus};
use super::stability;
use crate::chart::{Bar, ColourOf, GroupedBarChart, LineChart, Series, StackedBarChart};

/// Every chart kind this module draws (`Chart::kind`, report.json's `charts[].kind`): the
/// outputs page lists them all (tests/suite/docs.rs), and a test here reads the kinds the code
/// below writes against this list.
pub const CHART_KINDS: [&str; 11] = [
    "error-vs-time",
    "error-vs-spp",
    "passes",
    "queues",
    "simd",
    "speed-vs-memory",
    "warmup",
    "stability",
    "time-by-scene",
    "crossover",
    "shading-cost",
];

/// A drawn chart: file stem, kind, title, SVG text, and the group it belongs to.
pub struct Chart {
    pub stem: String,
    pub kind: &'static str,
    pub title: String,
    pub svg: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
}

impl Chart {
    /// A chart drawn across scenes at one resolution (`(0, 0)`: across resolutions too).
    fn across(kind: &'static str, stem: String, title: String, svg: String, (w, h): (u32, u32)) -> Self {
        Self { stem, kind, title, svg, scene: String::new(), width: w, height: h }
    }
}

/// Every chart the report's data supports (kinds without data in a group are left out).
pub fn charts(report: &ExperimentReport) -> Vec<Chart> {
    let mut groups: BTreeMap<(String, u32, u32), Vec<&RunRecord>> = BTreeMap::new();
    for r in report.runs.iter().filter(|r| r.status == RunStatus::Ok) {
        groups.entry((r.scene.clone(), r.width, r.height)).or_default().push(r);
    }
    let colours = MethodColours::of(report);
    let colour = |name: &str| colours.get(name);
    let mut out = Vec::new();
    for ((scene, w, h), mut runs) in groups {
        runs.sort_by_key(|r| r.index);
        let group = format!("{scene} {w}x{h}");
        let stem = |kind: &str| format!("{kind}-{}-{w}x{h}", file_safe(&scene));
        let mut push = |kind: &'static str, title: String, svg: String| {
            out.push(Chart { stem: stem(kind), kind, title, svg, scene: scene.clone(), width: w, height: h });
        };
        if let Some(c) = error_vs_time(&runs, &group) {
            push("error-vs-time", c.title.clone(), c.to_svg_with(&colour));
        }
        if let Some(c) = error_vs_spp(&runs, &group) {
            push("error-vs-spp", c.title.clone(), c.to_svg_with(&colour));
        }
        if let Some(c) = passes(&runs, &group) {
            push("passes", c.title.clone(), c.to_svg());
        }
        if let Some(c) = queues(&runs, &group) {
            push("queues", c.title.clone(), c.to_svg_with(&colour));
        }
        if let Some(c) = simd(&runs, &group) {
            push("simd", c.title.clone(), c.to_svg_with(&colour));
        }
        if let Some(c) = speed_vs_memory(&runs, &group) {
            push("speed-vs-memory", c.title.clone(), c.to_svg_with(&colour));
        }
        if let Some(c) = warmup(&runs, &group) {
            push("warmup", c.title.clone(), c.to_svg_with(&colour));
        }
        for (what, c) in stability(&runs, &group) {
            out.push(Chart {
                stem: format!("stability-{what}-{}-{w}x{h}", file_safe(&scene)),
                kind: "stability",
                title: c.title.clone(),
                svg: c.to_svg_with(&colour),
                scene: scene.clone(),
                width: w,
                height: h,
            });
        }
    }
    out.extend(time_by_scene(report, &colour));
    out.extend(crossover(report, &colour));
    out.extend(shading_cost(report, &colour));
    out
}

/// The scene the shading-cost axis measures against: the costly families (`rtiow-heavy-O`,
/// `rtiow-kinds-K`) are it with costly materials on its diffuse spheres.
const SHADING_BASELINE: &str = "rtiow-final";

/// The shading-cost axis (issue 46), per job settings where a config renders `rtiow-final` (the
/// axis's zero) and two or more scenes of the same geometry with costlier materials: each
/// wavefront variant's speed-up over the fastest megakernel against the scene's shading cost,
/// measured by the fastest megakernel as its extra nanoseconds per shaded hit over `rtiow-final`
/// (hits counted by a wavefront run's queues; per ray traced where a scene has no such run);
/// parity drawn at 1, and the cost at which each variant first crosses it named in the title
/// (the crossover).
fn shading_cost(report: &ExperimentReport, colour: ColourOf) -> Vec<Chart> {
    let threshold = stability::threshold_of(&report.config);
    let fastest = baseline::fastest_megakernel(report);
    let mut out = Vec::new();
    for ((w, h, spp, depth, nee, roulette), runs) in by_settings(report) {
        // A scene's fastest megakernel: its time and rays.
        let megakernel = |scene: &str| {
            runs.iter()
                .filter(|r| r.method == "megakernel" && r.scene == scene)
                .filter(|r| fastest.get(&baseline::job_key(r)).is_some_and(|b| Some(b.seconds) == r.seconds))
                .find_map(|r| Some((r.seconds?, r.rays?)))
        };
        let Some((base, _)) = megakernel(SHADING_BASELINE) else { continue };
        let mut scenes: Vec<&str> = Vec::new();
        for r in &runs {
            if !scenes.contains(&r.scene.as_str()) {
                scenes.push(&r.scene);
            }
        }
        // Per hit where every scene has a wavefront run that counted its hits (the queue
        // histogram's material queues: every shaded hit), else per ray traced (shadow rays too).
        let hits = |scene: &str| {
            runs.iter()
                .filter(|r| r.scene == scene)
                .filter_map(|r| Some(r.queue_histogram.as_ref()?.materials.iter().flatten().sum::<u64>()))
                .find(|&n| n > 0)
        };
        let per_hit = scenes.iter().all(|&s| hits(s).is_some());
        let unit = if per_hit { "hit" } else { "ray" };
        // The baseline itself is the axis's zero (its cost over itself).
        let cost: BTreeMap<&str, f64> = scenes
            .iter()
            .filter_map(|&s| {
                let (t, rays) = megakernel(s)?;
                let n = if per_hit { hits(s)? } else { rays };
                (n > 0).then(|| (s, 1e9 * (t - base) / n as f64))
            })
            .collect();
        if cost.len() < 3 {
            continue;
        }
        let mut series: Vec<Series> = Vec::new();
        for r in runs.iter().filter(|r| r.method == "wavefront" && cost.contains_key(r.scene.as_str())) {
            let Some(v) = baseline::versus_megakernel(r, &fastest, threshold) else { continue };
            let i = match series.iter().position(|s| s.name == r.label) {
                Some(i) => i,
                None => {
                    series.push(Series { name: r.label.clone(), ..Default::default() });
                    series.len() - 1
                }
            };
            series[i].points.push((cost[r.scene.as_str()], v.ratio));
            series[i].intervals.push(v.interval);
        }
        if series.is_empty() {
            continue;
        }
        let crossings: Vec<String> = series.iter_mut().map(|s| crossing(s, unit)).collect();
        let (lo, hi) =
            cost.values().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &c| (a.min(c), b.max(c)));
        series.push(Series {
            name: "parity (1×)".into(),
            points: vec![(lo, 1.0), (hi, 1.0)],
            ..Default::default()
        });
        let title = format!(
            "Speed-up over the fastest megakernel against shading cost: {w}x{h}, {spp} spp, depth {depth}{}. \
             Crossover: {}",
            settings_note(nee, roulette),
            crossings.join("; ")
        );
        // The drawing's own title stays short (a long one is cut); the report's names the crossovers.
        let chart = LineChart {
            title: format!(
                "Speed-up against shading cost: {w}x{h}, {spp} spp, depth {depth}{}",
                settings_note(nee, roulette)
            ),
            x_label: format!(
                "shading cost: the fastest megakernel's extra ns per {unit} over {SHADING_BASELINE}"
            ),
            y_label: "× the fastest megakernel (above 1: faster)".into(),
            series,
            ..Default::default()
        };
        let stem = format!("shading-cost-{w}x{h}-{spp}spp-d{depth}{}", settings_stem(nee, roulette));
        out.push(Chart::across("shading-cost", stem, title, chart.to_svg_with(colour), (w, h)));
    }
    out
}

/// Sorts a variant's points by cost and names where it crosses parity.
fn crossing(s: &mut Series, unit: &str) -> String {
    let mut order: Vec<usize> = (0..s.points.len()).collect();
    order.sort_by(|&a, &b| s.points[a].0.total_cmp(&s.points[b].0));
    s.points = order.iter().map(|&i| s.points[i]).collect();
    s.intervals = order.iter().map(|&i| s.intervals[i]).collect();
    match crossover_at(&s.points) {
        Some(x) if x > s.points[0].0 => format!("{} at {x:.1} ns/{unit}", s.name),
        Some(_) => format!("{} ahead from the start", s.name),
        None => format!("{} none", s.name),
    }
}

/// Where a curve of (cost, speed-up) points, in cost order, first rises through 1: linear
/// between the two points either side (the first point's cost when it starts at or above 1).
fn crossover_at(points: &[(f64, f64)]) -> Option<f64> {
    if points.first()?.1 >= 1.0 {
        return Some(points[0].0);
    }
    points.windows(2).find(|p| p[0].1 < 1.0 && p[1].1 >= 1.0).map(|p| {
        let ((x0, y0), (x1, y1)) = (p[0], p[1]);
        x0 + (1.0 - y0) * (x1 - x0) / (y1 - y0)
    })
}

/// The crossover chart, per scene (and depth and NEE where they vary): each GPU method variant's
/// speed-up over the fastest megakernel variant at the same job with the same numerical knobs and
/// stress transform, against the job's size in samples per frame; drawn where a scene has two or
/// more job sizes with a megakernel run. With several megakernel variants (naive and
/// regenerating), each gets its line too: the slower one below 1. Each point's bar is the
/// interval of its ratio (from the intervals of the two medians).
fn crossover(report: &ExperimentReport, colour: ColourOf) -> Vec<Chart> {
    let threshold = stability::threshold_of(&report.config);
    let ok: Vec<&RunRecord> =
        report.runs.iter().filter(|r| r.status == RunStatus::Ok && r.seconds.is_some()).collect();
    let mut by_scene: BTreeMap<(String, u32, bool, bool), Vec<&RunRecord>> = BTreeMap::new();
    for r in ok {
        by_scene.entry((r.scene.clone(), r.max_depth, r.nee, r.roulette)).or_default().push(r);
    }
    let fastest = baseline::fastest_megakernel(report);
    let mut out = Vec::new();
    for ((scene, depth, nee, roulette), runs) in by_scene {
        let sizes: BTreeSet<(u32, u32, u32)> = runs
            .iter()
            .filter(|r| r.method == "megakernel" && fastest.contains_key(&baseline::job_key(r)))
            .map(|r| (r.width, r.height, r.spp))
            .collect();
        if sizes.len() < 2 {
            continue;
        }
        // Series in the order their labels first appear (config order).
        // Per label: (point, the interval of its ratio).
        type Points = Vec<((f64, f64), (f64, f64))>;
        let mut series: Vec<(String, Points)> = Vec::new();
        let megakernels: BTreeSet<&str> =
            runs.iter().filter(|r| r.method == "megakernel").map(|r| r.label.as_str()).collect();
        let plotted = |r: &&&RunRecord| match r.method.as_str() {
            "cpu" | "cpu-f64" => false,
            "megakernel" => megakernels.len() > 1,
            _ => true,
        };
        for r in runs.iter().filter(plotted) {
            if let Some(v) = baseline::versus_megakernel(r, &fastest, threshold) {
                let samples = r.width as f64 * r.height as f64 * r.spp as f64;
                let point = ((samples, v.ratio), v.interval);
                match series.iter_mut().find(|(l, _)| *l == r.label) {
                    Some((_, points)) => points.push(point),
                    None => series.push((r.label.clone(), vec![point])),
                }
            }
        }
        if series.is_empty() {
            continue;
        }
        let series = series
            .into_iter()
            .map(|(name, mut points)| {
                points.sort_by(|a, b| a.0 .0.total_cmp(&b.0 .0));
                let (points, intervals) = points.into_iter().unzip();
                Series { name, points, intervals, labels: Vec::new() }
            })
            .collect();
        let nee_note = settings_note(nee, roulette);
        let title = format!("Speed-up over the fastest megakernel: {scene}, depth {depth}{nee_note}");
        let chart = LineChart {
            title: title.clone(),
            x_label: "samples per frame (width x height x spp)".into(),
            y_label: "speed-up over the megakernel (>1: faster; bars: its interval)".into(),
            x_log: true,
            y_log: true,
            x_zero: false,
            series,
        };
        let stem = format!("crossover-{}-d{depth}{}", file_safe(&scene), settings_stem(nee, roulette));
        let svg = chart.to_svg_with(colour);
        out.push(Chart { scene: scene.clone(), ..Chart::across("crossover", stem, title, svg, (0, 0)) });
    }
    out
}

/// Across scenes (a sweep such as rtiow-heavy-1..16 or spheres-1000..1000000): median time per
/// method variant, one chart per resolution, spp and depth shared by two or more scenes. Scenes
/// keep their config order.
fn time_by_scene(report: &ExperimentReport, colour: ColourOf) -> Vec<Chart> {
    let mut scene_order: Vec<&str> = Vec::new();
    for r in &report.runs {
        if !scene_order.contains(&r.scene.as_str()) {
            scene_order.push(&r.scene);
        }
    }
    let mut out = Vec::new();
    for ((w, h, spp, depth, nee, roulette), runs) in by_settings(report) {
        let scenes: Vec<&str> =
            scene_order.iter().copied().filter(|s| runs.iter().any(|r| r.scene == *s)).collect();
        if scenes.len() < 2 {
            continue;
        }
        let groups = scenes
            .iter()
            .map(|scene| {
                let bars = runs
                    .iter()
                    .filter(|r| r.scene == *scene)
                    .filter_map(|r| Some((r.label.clone(), r.seconds?)))
                    .collect();
                (scene.to_string(), bars)
            })
            .collect();
        let nee_note = settings_note(nee, roulette);
        let title = format!("Time by scene: {w}x{h}, {spp} spp, depth {depth}{nee_note}");
        let chart = GroupedBarChart {
            title: title.clone(),
            y_label: "median time per render, s".into(),
            y_max: None,
            percent: false,
            groups,
        };
        let stem = format!("time-by-scene-{w}x{h}-{spp}spp-d{depth}{}", settings_stem(nee, roulette));
        out.push(Chart::across("time-by-scene", stem, title, chart.to_svg_with(colour), (w, h)));
    }
    out
}

/// A job's settings but its scene: (width, height, spp, max depth, NEE, roulette).
type Settings = (u32, u32, u32, u32, bool, bool);

/// The ok runs by their settings, for the charts drawn across scenes (one chart each).
fn by_settings(report: &ExperimentReport) -> BTreeMap<Settings, Vec<&RunRecord>> {
    let mut settings: BTreeMap<Settings, Vec<&RunRecord>> = BTreeMap::new();
    for r in report.runs.iter().filter(|r| r.status == RunStatus::Ok) {
        settings.entry((r.width, r.height, r.spp, r.max_depth, r.nee, r.roulette)).or_default().push(r);
    }
    settings
}

/// `, NEE`, `, roulette`: the path settings a chart's title names when on.
fn settings_note(nee: bool, roulette: bool) -> String {
    format!("{}{}", if nee { ", NEE" } else { "" }, if roulette { ", roulette" } else { "" })
}

/// `-nee`, `-rr`: the same in a chart's file name (none when off, so earlier names stay).
fn settings_stem(nee: bool, roulette: bool) -> String {
    format!("{}{}", if nee { "-nee" } else { "" }, if roulette { "-rr" } else { "" })
}

/// Which render settings besides spp vary within a group, and so must name its series.
#[derive(Clone, Copy)]
struct Varying {
    depth: bool,
    nee: bool,
    roulette: bool,
}

impl Varying {
    fn of(runs: &[&RunRecord]) -> Self {
        Varying {
            depth: runs.iter().any(|r| r.max_depth != runs[0].max_depth),
            nee: runs.iter().any(|r| r.nee != runs[0].nee),
            roulette: runs.iter().any(|r| r.roulette != runs[0].roulette),
        }
    }

    /// ` d8`, ` NEE` / ` no NEE`, ` RR` / ` no RR`: the settings that tell this run's series apart.
    fn suffix(self, r: &RunRecord) -> String {
        let mut s = String::new();
        if self.depth {
            s += &format!(" d{}", r.max_depth);
        }
        if self.nee {
            s += if r.nee { " NEE" } else { " no NEE" };
        }
        if self.roulette {
            s += if r.roulette { " RR" } else { " no RR" };
        }
        s
    }
}

/// The series name of a run: its label, then the settings that vary in its group.
fn series_name(r: &RunRecord, varying: Varying) -> String {
    format!("{}{}", r.label, varying.suffix(r))
}

fn several_spps(runs: &[&RunRecord]) -> bool {
    runs.iter().any(|r| r.spp != runs[0].spp)
}

/// Speed against GPU memory (peak), log–log: one line per method variant through the values of
/// the knob that sizes its memory (the wavefront's `pool_size`, the megakernel's `threads`), at
/// the group's largest spp; drawn where the group's peaks differ.
fn speed_vs_memory(runs: &[&RunRecord], group: &str) -> Option<LineChart> {
    let max_spp = runs.iter().map(|r| r.spp).max()?;
    let varying = Varying::of(runs);
    let mut series: Vec<Series> = Vec::new();
    let mut peaks = BTreeSet::new();
    for r in runs.iter().filter(|r| r.spp == max_spp) {
        let (Some(m), Some(speed)) = (&r.memory, r.samples_per_second) else { continue };
        peaks.insert(m.peak);
        // The sweep's own knob is what the line runs through, so it leaves the name.
        let label: Vec<&str> =
            r.label.split(' ').filter(|p| !p.starts_with("pool=") && !p.starts_with("threads=")).collect();
        let name = format!("{}{}", label.join(" "), varying.suffix(r));
        let point = (m.peak as f64 / (1u64 << 20) as f64, speed * 1e-6);
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => series.push(Series { name, points: vec![point], ..Default::default() }),
        }
    }
    if peaks.len() < 2 {
        return None;
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    Some(LineChart {
        title: format!("Speed against GPU memory: {group}, {max_spp} spp"),
        x_label: "peak GPU memory, MiB".into(),
        y_label: "Msamples/s".into(),
        x_log: true,
        y_log: true,
        x_zero: false,
        series,
    })
}

/// Frame time against time since the warm-up began, one line per run whose warm-up rendered at
/// least [`WARMUP_TRACE_FRAMES`] frames: how long the device takes to reach steady frames (the
/// device step `warmup` runs a long, fixed warm-up to draw it).
fn warmup(runs: &[&RunRecord], group: &str) -> Option<LineChart> {
    let series: Vec<Series> = runs
        .iter()
        .filter_map(|r| {
            let log = r.warmup_log.as_ref().filter(|w| w.trace.len() >= WARMUP_TRACE_FRAMES)?;
            let points = log.trace.iter().map(|f| (f.at, 1e3 * f.seconds)).collect();
            Some(Series {
                name: format!("{} {}spp", r.label, r.spp),
                points,
                intervals: Vec::new(),
                labels: Vec::new(),
            })
        })
        .collect();
    (!series.is_empty()).then(|| LineChart {
        title: format!("Warm-up: frame time from the first frame on, {group}"),
        x_label: "seconds since the warm-up began".into(),
        y_label: "frame time, ms".into(),
        x_log: false,
        y_log: false,
        x_zero: false,
        series,
    })
}

/// Warm-ups this long get a chart.
pub const WARMUP_TRACE_FRAMES: usize = 10;

/// relMSE against time, log–log, one line per method variant through its spp values, each
/// point labelled with its spp.
fn error_vs_time(runs: &[&RunRecord], group: &str) -> Option<LineChart> {
    let varying = Varying::of(runs);
    let mut series: Vec<Series> = Vec::new();
    for r in runs {
        let (Some(m), Some(t)) = (&r.error_metrics, r.seconds) else { continue };
        let name = series_name(r, varying);
        let i = match series.iter().position(|s| s.name == name) {
            Some(i) => i,
            None => {
                series.push(Series { name, ..Default::default() });
                series.len() - 1
            }
        };
        series[i].points.push((t, m.relmse));
        series[i].labels.push(format!("{} spp", r.spp));
    }
    for s in &mut series {
        let mut order: Vec<usize> = (0..s.points.len()).collect();
        order.sort_by(|&a, &b| s.points[a].0.total_cmp(&s.points[b].0));
        s.points = order.iter().map(|&i| s.points[i]).collect();
        s.labels = order.iter().map(|&i| s.labels[i].clone()).collect();
    }
    (!series.is_empty()).then(|| LineChart {
        title: format!("Error against time (points: spp): {group}"),
        x_label: "time per render, s (frame time for GPU methods, wall time for CPU ones)".into(),
        y_label: "relMSE".into(),
        x_log: true,
        y_log: true,
        x_zero: false,
        series,
    })
}

/// relMSE against spp, log–log, one line per method variant: where the error stops falling as
/// 1/spp (f32's floor, in a precision study); drawn where the group has several spps.
fn error_vs_spp(runs: &[&RunRecord], group: &str) -> Option<LineChart> {
    let measured: Vec<&&RunRecord> = runs.iter().filter(|r| r.error_metrics.is_some()).collect();
    if measured.iter().all(|r| r.spp == measured[0].spp) {
        return None;
    }
    let varying = Varying::of(runs);
    let mut series: Vec<Series> = Vec::new();
    for r in measured {
        let point = (r.spp as f64, r.error_metrics.as_ref().expect("filtered").relmse);
        let name = series_name(r, varying);
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => series.push(Series { name, points: vec![point], ..Default::default() }),
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    Some(LineChart {
        title: format!("Error against spp: {group}"),
        x_label: "samples per pixel".into(),
        y_label: "relMSE".into(),
        x_log: true,
        y_log: true,
        x_zero: false,
        series,
    })
}

/// A run's scale factor (1 where not recorded).
fn scale_of(r: &RunRecord) -> f64 {
    r.options.get("scale").and_then(Value::as_f64).unwrap_or(1.0)
}

/// How far a run's scene was moved: |translate| (0 where not recorded).
fn distance_of(r: &RunRecord) -> f64 {
    let t = r.options.get("translate").and_then(Value::as_array);
    let c = |i: usize| t.and_then(|t| t.get(i)?.as_f64()).unwrap_or(0.0);
    crate::scene::stress::StressTransform { scale: 1.0, translate: [c(0), c(1), c(2)] }.distance()
}

/// A stress transform as the stability charts plot it.
struct StressAxis {
    /// Names the chart's file: `stability-{key}-…`.
    key: &'static str,
    /// The label part of the knob, dropped from series names (the line runs through its values).
    label_prefix: &'static str,
    value: fn(&RunRecord) -> f64,
    noun: &'static str,
    x_label: &'static str,
}

const STRESS_AXES: [StressAxis; 2] = [
    StressAxis {
        key: "scale",
        label_prefix: "scale=",
        value: scale_of,
        noun: "scale",
        x_label: "scale factor",
    },
    StressAxis {
        key: "translate",
        label_prefix: "translate=",
        value: distance_of,
        noun: "translation",
        x_label: "distance moved |translate|, scene units",
    },
];

/// Where runs of a group differ in `scale` (or in `translate`): relMSE against the scale factor
/// (against the distance |translate|, 0 drawn at its own tick), log–log, one line per method
/// variant with the transform's part of its label removed; and the self-hits of a render,
/// secondary plus shadow rays, as counts + 1 (so that none sits at 1 on the log axis) against it.
/// Returns (file-name part, chart) pairs.
fn stability(runs: &[&RunRecord], group: &str) -> Vec<(String, LineChart)> {
    // Runs in both render spaces: one set of charts per space, named by it (`translate-camera`),
    // so that each line is one method variant and the legend need not name the space.
    let space = |r: &RunRecord| r.options.get("render_space").and_then(Value::as_str).map(str::to_owned);
    let spaces: BTreeSet<String> = runs.iter().filter_map(|r| space(r)).collect();
    if spaces.len() < 2 {
        return stability_charts(runs, group, "");
    }
    let mut out = Vec::new();
    for s in &spaces {
        let of: Vec<&RunRecord> = runs.iter().copied().filter(|r| space(r).as_ref() == Some(s)).collect();
        for (key, chart) in stability_charts(&of, &format!("{group}, {s} space"), "render-space=") {
            let key = match key.split_once('-') {
                Some((axis, rest)) => format!("{axis}-{s}-{rest}"),
                None => format!("{key}-{s}"),
            };
            out.push((key, chart));
        }
    }
    out
}

/// [`stability`] over runs of one render space; `drop` is a label part (besides the stress
/// axis's) left out of series names, or "".
fn stability_charts(runs: &[&RunRecord], group: &str, drop: &str) -> Vec<(String, LineChart)> {
    let varying = Varying::of(runs);
    let spps = several_spps(runs);
    let mut out = Vec::new();
    for axis in &STRESS_AXES {
        let name = |r: &RunRecord| {
            let label: Vec<&str> = r
                .label
                .split(' ')
                .filter(|p| !p.starts_with(axis.label_prefix) && (drop.is_empty() || !p.starts_with(drop)))
                .collect();
            let spp = if spps { format!(" {}spp", r.spp) } else { String::new() };
            format!("{}{spp}{}", label.join(" "), varying.suffix(r))
        };
        let chart = |title: String, y_label: &str, point: &dyn Fn(&RunRecord) -> Option<f64>| {
            let mut series: Vec<Series> = Vec::new();
            let mut xs = BTreeSet::new();
            for r in runs {
                let Some(y) = point(r) else { continue };
                let x = (axis.value)(r);
                xs.insert(x.to_bits());
                let name = name(r);
                match series.iter_mut().find(|s| s.name == name) {
                    Some(s) => s.points.push((x, y)),
                    None => series.push(Series {
                        name,
                        points: vec![(x, y)],
                        intervals: Vec::new(),
                        labels: Vec::new(),
                    }),
                }
            }
            for s in &mut series {
                s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            (xs.len() >= 2).then(|| LineChart {
                title,
                x_label: axis.x_label.into(),
                y_label: y_label.into(),
                x_log: true,
                y_log: true,
                x_zero: true,
                series,
            })
        };
        let relmse = |r: &RunRecord| r.error_metrics.as_ref().map(|m| m.relmse);
        if let Some(c) = chart(
            format!("Error under {}: {group}", axis.noun),
            "relMSE against the untransformed reference",
            &relmse,
        ) {
            out.push((axis.key.to_string(), c));
        }
        let self_hits = |r: &RunRecord| Some((r.self_hits? + r.shadow_self_hits.unwrap_or(0)) as f64 + 1.0);
        if let Some(c) = chart(
            format!("Self-hits under {} (none drawn at 1): {group}", axis.noun),
            "secondary + shadow self-hits + 1, per render",
            &self_hits,
        ) {
            out.push((format!("{}-self-hits", axis.key), c));
        }
    }
    out
}

/// The label of a run among others of its group: variant, then spp, depth and NEE where they
/// vary.
fn bar_label(r: &RunRecord, runs: &[&RunRecord]) -> String {
    let mut s = r.label.clone();
    if several_spps(runs) {
        s += &format!(" {}spp", r.spp);
    }
    s + &Varying::of(runs).suffix(r)
}

/// Median GPU milliseconds per pass label, stacked, one bar per GPU run.
fn passes(runs: &[&RunRecord], group: &str) -> Option<StackedBarChart> {
    let bars: Vec<Bar> = runs
        .iter()
        .filter(|r| !r.passes.is_empty())
        .map(|r| Bar {
            label: bar_label(r, runs),
            segments: r.passes.iter().map(|(k, p)| (k.clone(), p.seconds.median * 1e3)).collect(),
        })
        .collect();
    (!bars.is_empty()).then(|| StackedBarChart {
        title: format!("GPU time per pass: {group}"),
        // Per-pass times come from a render of their own with a timestamp around every pass
        // (the timed repetitions run without them), so the bars need not add up to the table's
        // frame time.
        y_label: "GPU ms per render (profiled, median)".into(),
        bars,
    })
}

/// The fraction of paths still in the ray queue at each bounce (wavefront runs at the group's
/// largest spp: occupancy hardly depends on spp).
fn queues(runs: &[&RunRecord], group: &str) -> Option<LineChart> {
    let max_spp = runs.iter().map(|r| r.spp).max()?;
    let varying = Varying::of(runs);
    let series: Vec<Series> = runs
        .iter()
        .filter(|r| r.spp == max_spp)
        .filter_map(|r| {
            let h = r.queue_histogram.as_ref()?;
            let first = *h.rays.first()? as f64;
            let points = h
                .rays
                .iter()
                .enumerate()
                .take_while(|(_, &n)| n > 0)
                .map(|(b, &n)| (b as f64, n as f64 / first))
                .collect();
            Some(Series { name: series_name(r, varying), points, ..Default::default() })
        })
        .collect();
    (!series.is_empty()).then(|| LineChart {
        title: format!("Queue occupancy per bounce: {group}, {max_spp} spp"),
        x_label: "bounce".into(),
        y_label: "paths traced / paths started".into(),
        x_log: false,
        y_log: true,
        x_zero: false,
        series,
    })
}

/// SIMD efficiency per pass or point, one bar per run at the group's largest spp (efficiency
/// hardly depends on spp), where measured.
fn simd(runs: &[&RunRecord], group: &str) -> Option<GroupedBarChart> {
    let max_spp = runs.iter().map(|r| r.spp).max()?;
    let measured: Vec<&&RunRecord> =
        runs.iter().filter(|r| r.spp == max_spp && r.simd.as_ref().is_some_and(|s| !s.is_empty())).collect();
    if measured.is_empty() {
        return None;
    }
    let mut groups: BTreeMap<String, Vec<(String, f64)>> = BTreeMap::new();
    for r in &measured {
        for (point, e) in r.simd.as_ref().expect("filtered") {
            groups.entry(point.clone()).or_default().push((bar_label(r, runs), e.efficiency));
        }
    }
    Some(GroupedBarChart {
        title: format!("SIMD efficiency (active / available lanes): {group}, {max_spp} spp"),
        y_label: "SIMD efficiency".into(),
        y_max: Some(1.0),
        percent: true,
        groups: groups.into_iter().collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::{crossover_at, CHART_KINDS};

    /// The kinds written in this file (`push("kind", …)`, `kind: "kind"`, `Chart::across("kind",
    /// …)`) are [`CHART_KINDS`].
    #[test]
    fn every_kind_drawn_is_listed() {
        let code = include_str!("charts.rs");
        let code = &code[..code.find("#[cfg(test)]").unwrap()];
        let mut written: Vec<&str> = Vec::new();
        for marker in ["push(\"", "kind: \"", "Chart::across(\""] {
            for (i, _) in code.match_indices(marker) {
                let rest = &code[i + marker.len()..];
                written.push(&rest[..rest.find('"').unwrap()]);
            }
        }
        written.sort();
        written.dedup();
        let mut listed = CHART_KINDS.to_vec();
        listed.sort();
        assert_eq!(written, listed);
    }

    #[test]
    fn the_crossover_is_where_the_speed_up_first_rises_through_one() {
        assert_eq!(crossover_at(&[(0.0, 0.5), (10.0, 1.5)]), Some(5.0));
        assert_eq!(crossover_at(&[(0.0, 0.5), (10.0, 0.9), (20.0, 1.3), (30.0, 0.8)]), Some(12.5));
        assert_eq!(crossover_at(&[(2.0, 1.2), (10.0, 1.5)]), Some(2.0), "above parity from the start");
        assert_eq!(crossover_at(&[(0.0, 0.5), (10.0, 0.9)]), None);
        assert_eq!(crossover_at(&[]), None);
    }
}
