//! Experiments end to end: configs are validated whole with clear errors; reports match the
//! documented JSON Schema; failed runs are recorded while others go on; a killed experiment
//! leaves its last complete report; shards merge into the report an unsharded run gives. (Resuming
//! a killed experiment: `resume.rs`; the CSV tables beside report.json: `tidy.rs`.)

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use wavetrace::experiment::merge::merge;
use wavetrace::experiment::plan::{plan, Shard};
use wavetrace::experiment::report::{ExperimentReport, ReportStatus, RunStatus};
use wavetrace::experiment::resume::Resume;
use wavetrace::experiment::runner::{self, RunnerOptions};
use wavetrace::experiment::ExperimentConfig;
use wavetrace::image_io::{read_exr, RgbImage};

pub fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::tmp().join("experiment").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn wavetrace(args: &[&str]) -> Output {
    Command::new(crate::common::bin()).args(args).output().expect("run wavetrace")
}

/// `wavetrace experiment run CONFIG --out OUT --cache CACHE`.
pub fn run_experiment(config: &Path, out: &Path, cache: &Path) -> Output {
    run_experiment_with(config, out, cache, &[])
}

/// [`run_experiment`] with `extra` arguments after the config.
pub fn run_experiment_with(config: &Path, out: &Path, cache: &Path, extra: &[&str]) -> Output {
    let arg = |p: &Path| p.to_str().unwrap().to_owned();
    let mut args = vec!["experiment".into(), "run".into(), arg(config)];
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(["--out".into(), arg(out), "--cache".into(), arg(cache)]);
    wavetrace(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Writes `config` into `dir/name.json` and returns its path.
pub fn write_config(dir: &Path, name: &str, config: &Value) -> PathBuf {
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(config).unwrap()).unwrap();
    path
}

/// Checks `report.json` in `dir` against experiments/report.schema.json with the reference
/// validator (scripts/check_schema.py, Python's `jsonschema`, in the venv scripts/test.sh makes:
/// `WAVETRACE_EXR_PYTHON`); without that Python the check is listed as skipped. Returns the report.
pub fn assert_valid(dir: &Path) -> Value {
    let report_path = dir.join("report.json");
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    let Some(python) =
        crate::common::third_party_python("report.json against experiments/report.schema.json")
    else {
        return report;
    };
    let root = crate::common::root();
    let out = std::process::Command::new(python)
        .arg(root.join("scripts/check_schema.py"))
        .arg(root.join("experiments/report.schema.json"))
        .arg(&report_path)
        .output()
        .expect("run scripts/check_schema.py");
    assert!(
        out.status.success(),
        "report.json in {} breaks the schema:\n{}{}",
        dir.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    report
}

pub fn small_config(methods: Value) -> Value {
    serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres"],
        "resolutions": ["40x24"],
        "spp": [2, 8],
        "max_depth": [8],
        "repetitions": 2,
        "warmup": 1,
        "methods": methods,
        "reference": {"method": "cpu-f64", "spp": 64}
    })
}

#[test]
fn full_report_matches_the_schema_and_holds_every_output() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("full");
    let mut config = small_config(serde_json::json!([
        {"method": "cpu"},
        {"method": "megakernel"},
        {"method": "wavefront", "schedule": "waves", "compaction": ["atomic", "scan"]}
    ]));
    config["instrument"] = Value::Bool(true);
    let path = write_config(&dir, "full", &config);
    let out = dir.join("out");
    let cache = dir.join("cache");
    let o = run_experiment(&path, &out, &cache);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = assert_valid(&out);
    assert_eq!(json["status"], "complete");
    // Tidy tables beside it, with every pass (and SIMD point) of the GPU runs.
    let (header, rows) = crate::tidy::assert_tidy(&out);
    // The GPU-only columns are filled where they apply, so the check above is not of empty cells.
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let wavefront: Vec<_> = rows.iter().filter(|r| r[col("method")] == "wavefront").collect();
    assert!(!wavefront.is_empty());
    for name in ["memory_total", "memory_peak", "memory_queues", "memory_path_state"] {
        assert!(wavefront.iter().all(|r| !r[col(name)].is_empty()), "wavefront {name} filled");
    }
    let report = ExperimentReport::read(&out).unwrap();
    assert_eq!(report.runs.len(), 8);
    assert_eq!(report.runs_planned, 8);
    // The directory is self-contained: each reference's EXR is inside it, the same bytes as
    // the cached one the runs were measured against.
    assert!(!report.references.is_empty());
    for r in &report.references {
        let copy = out.join(r.exr_copy.as_ref().expect("the reference's EXR is kept"));
        assert!(copy.starts_with(out.join("references")), "{}", copy.display());
        assert_eq!(std::fs::read(&copy).unwrap(), std::fs::read(&r.exr).unwrap(), "{}", r.key);
    }

    let cpu: Vec<_> = report.runs.iter().filter(|r| r.method == "cpu").collect();
    for r in &report.runs {
        assert_eq!(r.status, RunStatus::Ok, "{}: {:?}", r.id, r.error);
        assert_eq!(r.repeatable, Some(true), "{}: repetitions of one seed give one image", r.id);
        let images = r.images.as_ref().unwrap();
        for f in [&images.exr, &images.png, images.error_map.as_ref().unwrap()] {
            assert!(out.join(f).is_file(), "{} is missing", f);
        }
        let (img, _) = wavetrace::image_io::read_exr(out.join(&images.exr)).unwrap();
        assert_eq!((img.width, img.height), (40, 24));
        let m = r.error_metrics.as_ref().unwrap();
        let t = r.seconds.unwrap();
        assert!((r.efficiency.unwrap() - 1.0 / (m.relmse * t)).abs() <= 1e-9 * r.efficiency.unwrap());
        assert_eq!(r.wall_seconds.as_ref().unwrap().values.len(), 2);
        // Same paths on every method: errors against the reference agree with the CPU's.
        let twin = cpu.iter().find(|c| c.spp == r.spp).unwrap();
        let m0 = twin.error_metrics.as_ref().unwrap();
        assert!(
            (m.relmse - m0.relmse).abs() <= 0.01 * m0.relmse,
            "{}: relMSE {} vs cpu {}",
            r.id,
            m.relmse,
            m0.relmse
        );
        assert!(r.rays.unwrap() >= r.samples, "{}: at least one ray per sample", r.id);
        if r.method == "wavefront" {
            assert!(r.queue_histogram.is_some() && r.passes.contains_key("intersect"));
            // What the schedule cost: every pass dispatched, the empty ones, the occupancy.
            let occupancy = r.intersect_occupancy.unwrap();
            assert!(occupancy > 0.0 && occupancy <= 1.0, "{}: {occupancy}", r.id);
            assert!(r.empty_dispatches.unwrap() < r.dispatches.unwrap());
            assert_eq!(r.iterations, Some(8), "{}: max depth 8, one wave", r.id);
        }
        if r.method == "megakernel" {
            assert_eq!(r.empty_dispatches, Some(0));
        }
        if r.method != "cpu" {
            assert!(r.gpu_seconds.is_some() && !r.passes.is_empty());
            if common::gpu().unwrap().summary.timestamps {
                // Timed without per-pass timestamps (two frames), profiled once with them: the
                // per-pass times and their sum come from that one render alone.
                assert_eq!(r.frame_seconds.as_ref().unwrap().values.len(), 2, "{}", r.id);
                assert_eq!(r.gpu_seconds.as_ref().unwrap().values.len(), 1, "{}", r.id);
                assert_eq!(r.passes.values().next().unwrap().seconds.values.len(), 1, "{}", r.id);
                assert_eq!(r.time_source.as_deref(), Some("timestamps"), "{}", r.id);
                // Not compared with the sum of passes: passes without a barrier between them can
                // overlap on llvmpipe, so the sum can exceed the frame (seen under load in CI).
                assert!(r.profiled_frame_seconds.unwrap() > 0.0, "{}", r.id);
                assert!(r.between_passes_seconds.is_some(), "{}", r.id);
            }
            let subgroups = common::gpu().unwrap().summary.subgroups;
            assert_eq!(r.simd.is_some(), subgroups, "{}: SIMD efficiency where subgroups exist", r.id);
            // The intersect pass's coherence counters: wavefront runs only (issue 26).
            let coherent = r.coherence.as_ref().is_some_and(|c| c.iter().any(|b| b.subgroups > 0));
            assert_eq!(coherent, subgroups && r.method == "wavefront", "{}: coherence counters", r.id);
        }
    }
    // Error falls with spp.
    let by_spp = |spp: u32| cpu.iter().find(|c| c.spp == spp).unwrap().error_metrics.as_ref().unwrap().relmse;
    assert!(by_spp(8) < by_spp(2));

    // One reference, rendered once, with a different seed from the runs.
    assert_eq!(report.references.len(), 1);
    let reference = &report.references[0];
    assert!(!reference.cached && reference.seed != Some(0));
    assert!(out.join(reference.png.as_ref().unwrap()).is_file());

    // Charts and the page.
    let kinds: Vec<&str> = report.charts.iter().map(|c| c.kind.as_str()).collect();
    for k in ["error-vs-time", "passes", "queues"] {
        assert!(kinds.contains(&k), "no {k} chart in {kinds:?}");
    }
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert_eq!(html.matches("<svg").count(), report.charts.len(), "every chart inline");
    assert!(
        html.matches("data:image/png;base64,").count() >= 3 * report.runs.len(),
        "run, reference and error map for each run"
    );
    for r in &report.runs {
        assert!(html.contains(&r.id));
    }
    assert!(html.contains("dispatches (empty)") && html.contains("occupancy"));
    for c in &report.charts {
        let svg = std::fs::read_to_string(out.join(&c.file)).unwrap();
        assert!(svg.contains("<svg") && !svg.contains("NaN"));
    }

    // A rerun takes the reference from the cache and measures the same errors.
    let again = dir.join("again");
    let o = run_experiment(&path, &again, &cache);
    assert!(o.status.success());
    let second = ExperimentReport::read(&again).unwrap();
    assert!(second.references[0].cached);
    for (a, b) in report.runs.iter().zip(&second.runs) {
        assert_eq!(a.error_metrics, b.error_metrics, "{}", a.id);
    }

    // `experiment report` re-draws the page from report.json alone.
    std::fs::remove_file(out.join("report.html")).unwrap();
    let o = wavetrace(&["experiment", "report", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("report.html").is_file());
    assert_valid(&out);
}

#[test]
fn a_failed_run_is_recorded_and_the_others_go_on() {
    let dir = scratch("failed");
    let mut config = small_config(serde_json::json!([{"method": "cpu"}, {"method": "megakernel"}]));
    // No adapter has this name, so every GPU run fails, on any machine.
    config["adapter"] = Value::String("no-such-adapter-anywhere".into());
    let path = write_config(&dir, "failed", &config);
    let out = dir.join("out");
    let o = run_experiment(&path, &out, &dir.join("cache"));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "failed runs make the exit status fail");
    assert!(stderr.contains("2 of 4 runs failed") && !stderr.contains("panicked"), "{stderr}");
    assert_valid(&out);
    let report = ExperimentReport::read(&out).unwrap();
    assert_eq!(report.status, ReportStatus::Complete);
    for r in &report.runs {
        if r.method == "megakernel" {
            assert_eq!(r.status, RunStatus::Failed);
            assert!(r.error.as_ref().unwrap().contains("no-such-adapter-anywhere"), "{:?}", r.error);
            assert!(r.images.is_none() && r.seconds.is_none());
        } else {
            assert_eq!(r.status, RunStatus::Ok, "{:?}", r.error);
        }
    }
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("FAILED"));
}

/// Reads `dir/report.json` if it exists; it must always be complete JSON.
pub fn read_if_any(dir: &Path) -> Option<Value> {
    let text = std::fs::read_to_string(dir.join("report.json")).ok()?;
    Some(
        serde_json::from_str(&text)
            .unwrap_or_else(|e| panic!("truncated or corrupt report.json: {e}\n{text}")),
    )
}

#[test]
fn a_killed_experiment_leaves_its_last_complete_report() {
    let dir = scratch("killed");
    let config = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres", "rtiow-final"],
        "resolutions": ["64x36", "48x27"],
        "spp": [1, 2, 3, 4, 5, 6, 7, 8],
        "repetitions": 3,
        "warmup": 0,
        "methods": [{"method": "cpu"}, {"method": "cpu-f64"}]
    });
    let path = write_config(&dir, "killed", &config);
    // Kill at several moments; whatever instant the kill lands, report.json is whole.
    for (attempt, runs_before_kill) in [1usize, 3, 6].into_iter().enumerate() {
        let out = dir.join(format!("out{attempt}"));
        let mut child = Command::new(crate::common::bin())
            .args(["experiment", "run", path.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        let seen = loop {
            if let Some(r) = read_if_any(&out) {
                let n = r["runs"].as_array().unwrap().len();
                if n >= runs_before_kill {
                    break n;
                }
            }
            assert!(start.elapsed() < Duration::from_secs(120), "the experiment made no progress");
            std::thread::sleep(Duration::from_millis(5));
        };
        child.kill().unwrap();
        child.wait().unwrap();
        let report = assert_valid(&out);
        assert_eq!(report["status"], "running", "a killed experiment never claims to be complete");
        let runs = report["runs"].as_array().unwrap();
        assert!(runs.len() >= seen && runs.len() < 64, "{} runs after seeing {seen}", runs.len());
        for r in runs {
            assert_eq!(r["status"], "ok");
            assert!(
                out.join(r["images"]["exr"].as_str().unwrap()).is_file(),
                "a recorded run's image exists"
            );
        }
        // The partial report can still be drawn.
        let o = wavetrace(&["experiment", "report", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

/// What must not differ between an unsharded run and merged shards: everything but timings
/// (their warm-ups and stability too), provenance, where the reference came from, and which runs
/// took turns (a shard's runs take turns only with the same shard's).
fn comparable(report: &ExperimentReport) -> Value {
    let mut v = serde_json::to_value(report).unwrap();
    v["environments"] = Value::Null;
    for r in v["runs"].as_array_mut().unwrap() {
        let o = r.as_object_mut().unwrap();
        for k in [
            "environment",
            "wall_seconds",
            "gpu_seconds",
            "frame_seconds",
            "host_gap_seconds",
            "between_passes_seconds",
            "profiled_frame_seconds",
            "seconds",
            "passes",
            "passes_per_bounce",
            "samples_per_second",
            "rays_per_second",
            "efficiency",
            "warmup_log",
            "stability",
            "interleaved_with",
            "scene_prepare_seconds",
            "bvh_build_seconds",
            "preheat_seconds",
        ] {
            o.remove(k);
        }
        // The modelled path-state traffic's counts compare; its passes' times do not.
        if let Some(passes) = o.get_mut("state_traffic").and_then(|t| t.get_mut("passes")) {
            for p in passes.as_array_mut().unwrap() {
                let p = p.as_object_mut().unwrap();
                p.remove("seconds");
                p.remove("bytes_per_second");
            }
        }
    }
    for r in v["references"].as_array_mut().unwrap() {
        let o = r.as_object_mut().unwrap();
        for k in ["cached", "render_seconds"] {
            o.remove(k);
        }
    }
    v
}

#[test]
fn shards_merge_into_the_report_of_an_unsharded_run() {
    let dir = scratch("shards");
    let methods = if common::gpu().is_some() {
        serde_json::json!([{"method": "cpu"}, {"method": "megakernel"}, {"method": "wavefront"}])
    } else {
        serde_json::json!([{"method": "cpu"}, {"method": "cpu-f64"}])
    };
    let path = write_config(&dir, "sweep", &small_config(methods));
    let config = ExperimentConfig::from_file(&path).unwrap();
    let cache = dir.join("cache");
    let run = |out: &str, shard: Option<Shard>| {
        let opts =
            RunnerOptions { out_dir: dir.join(out), shard, cache_dir: cache.clone(), resume: Resume::Off };
        runner::run(&config, &opts).unwrap()
    };
    let whole = run("whole", None);
    let shards: Vec<PathBuf> = (0..4)
        .map(|i| {
            let r = run(&format!("shard{i}"), Some(Shard { index: i, count: 4 }));
            assert_eq!(r.runs_selected, plan(&config).iter().filter(|p| p.index % 4 == i as usize).count());
            dir.join(format!("shard{i}"))
        })
        .collect();
    let merged = merge(&shards, &dir.join("merged")).unwrap();
    assert_valid(&dir.join("merged"));
    crate::tidy::assert_tidy(&dir.join("merged"));
    assert_eq!(merged.status, ReportStatus::Complete);
    assert_eq!(merged.environments.len(), 4);
    assert_eq!(comparable(&merged), comparable(&whole));
    for r in &merged.runs {
        let images = r.images.as_ref().unwrap();
        assert!(dir.join("merged").join(&images.exr).is_file());
        assert_eq!(merged.environments[r.environment].shard.unwrap().index as usize, r.index % 4);
    }

    // A missing shard: the merge says which runs are missing.
    let partial = merge(&shards[..3], &dir.join("partial")).unwrap();
    assert_eq!(partial.status, ReportStatus::Incomplete);
    let expected: Vec<usize> = (0..whole.runs.len()).filter(|i| i % 4 == 3).collect();
    assert_eq!(partial.missing_runs, expected);
    // The same shard twice, or shards of different configs, are refused.
    let twice = merge(&[shards[0].clone(), shards[0].clone()], &dir.join("twice")).unwrap_err();
    assert!(format!("{twice:#}").contains("is in both"), "{twice:#}");
    let other_path = write_config(&dir, "other", &small_config(serde_json::json!([{"method": "cpu"}])));
    let other = ExperimentConfig::from_file(&other_path).unwrap();
    runner::run(
        &other,
        &RunnerOptions {
            out_dir: dir.join("other"),
            shard: None,
            cache_dir: cache.clone(),
            resume: Resume::Off,
        },
    )
    .unwrap();
    let mixed = merge(&[shards[0].clone(), dir.join("other")], &dir.join("mixed")).unwrap_err();
    assert!(format!("{mixed:#}").contains("different configs"), "{mixed:#}");
}

/// Each bad config gives an error naming the file, the JSON path and the reason.
#[test]
fn bad_configs_name_the_file_the_field_and_the_reason() {
    let dir = scratch("bad");
    let good = small_config(serde_json::json!([{"method": "cpu"}, {"method": "wavefront"}]));
    let path = write_config(&dir, "good", &good);
    ExperimentConfig::from_file(&path).expect("the base config is valid");

    // (file name, edit of the good config, expected JSON path, expected words of the reason)
    type Case = (&'static str, Box<dyn Fn(&mut Value)>, &'static str, &'static str);
    let cases: Vec<Case> = vec![
        (
            "no-schema",
            Box::new(|c| drop(c.as_object_mut().unwrap().remove("schema"))),
            "",
            "missing required field \"schema\"",
        ),
        (
            "new-schema",
            Box::new(|c| c["schema"] = "wavetrace-experiment/9".into()),
            "schema",
            "unsupported schema",
        ),
        ("typo", Box::new(|c| c["repetitons"] = 3.into()), "repetitons", "did you mean \"repetitions\""),
        ("no-question", Box::new(|c| c["question"] = " ".into()), "question", "what question"),
        ("spp-zero", Box::new(|c| c["spp"] = serde_json::json!([4, 0])), "spp[1]", "must be in 1..="),
        ("spp-repeat", Box::new(|c| c["spp"] = serde_json::json!([4, 4])), "spp[1]", "repeats"),
        (
            "resolution",
            Box::new(|c| c["resolutions"] = serde_json::json!(["100by50"])),
            "resolutions[0]",
            "WIDTHxHEIGHT",
        ),
        ("empty-methods", Box::new(|c| c["methods"] = serde_json::json!([])), "methods", "at least one"),
        (
            "roulette-word",
            Box::new(|c| c["roulette"] = serde_json::json!([false, "pbrt"])),
            "roulette[1]",
            "expected true or false",
        ),
        (
            "roulette-repeat",
            Box::new(|c| c["roulette"] = serde_json::json!([true, true])),
            "roulette[1]",
            "repeats",
        ),
        (
            "matched-reference-roulette",
            Box::new(|c| {
                c["reference"] = serde_json::json!({"method": "cpu-f64", "spp": "match", "roulette": true})
            }),
            "reference.roulette",
            "drop this field",
        ),
        (
            "bad-method",
            Box::new(|c| c["methods"][0]["method"] = "wavefrnt".into()),
            "methods[0].method",
            "did you mean \"wavefront\"",
        ),
        (
            "chunks-without-regeneration",
            Box::new(|c| c["methods"][1]["chunk_pools"] = 16.into()),
            "methods[1].chunk_pools",
            "needs \"schedule\": \"regenerate\"",
        ),
        (
            "chunk-pools-zero",
            Box::new(|c| {
                c["methods"][1]["chunk_pools"] = 0.into();
                c["methods"][1]["schedule"] = "regenerate".into();
            }),
            "methods[1].chunk_pools",
            "must be in 1..=1024",
        ),
        (
            "slot-order-without-queues",
            Box::new(|c| {
                c["methods"][1]["queue_order"] = "slot".into();
                c["methods"][1]["compaction"] = "off".into();
            }),
            "methods[1].queue_order",
            "it needs \"compaction\": \"atomic\" or \"scan\"",
        ),
        (
            "slot-depth-order-without-queues",
            Box::new(|c| {
                c["methods"][1]["queue_order"] = "slot-depth".into();
                c["methods"][1]["compaction"] = "off".into();
            }),
            "methods[1].queue_order",
            "\"slot-depth\" orders the queues",
        ),
        (
            "bad-queue-order",
            Box::new(|c| {
                c["methods"][1]["queue_order"] = "sorted".into();
                c["methods"][1]["compaction"] = "scan".into();
            }),
            "methods[1].queue_order",
            "\"auto\", \"arrival\", \"slot\" or \"slot-depth\"",
        ),
        (
            "refill-below-without-regeneration",
            Box::new(|c| c["methods"][1]["refill_below"] = 0.5.into()),
            "methods[1].refill_below",
            "needs \"schedule\": \"regenerate\"",
        ),
        (
            "refill-below-zero",
            Box::new(|c| {
                c["methods"][1]["refill_below"] = 0.into();
                c["methods"][1]["schedule"] = "regenerate".into();
            }),
            "methods[1].refill_below",
            "in (0, 1], got 0",
        ),
        (
            "compact-states-without-regeneration",
            Box::new(|c| c["methods"][1]["compact_states"] = "on".into()),
            "methods[1].compact_states",
            "needs \"schedule\": \"regenerate\"",
        ),
        (
            "compact-states-without-queues",
            Box::new(|c| {
                c["methods"][1]["compact_states"] = "on".into();
                c["methods"][1]["schedule"] = "regenerate".into();
                c["methods"][1]["compaction"] = "off".into();
            }),
            "methods[1].compact_states",
            "it needs \"compaction\": \"atomic\" or \"scan\"",
        ),
        (
            "bad-compact-states",
            Box::new(|c| {
                c["methods"][1]["compact_states"] = "yes".into();
                c["methods"][1]["schedule"] = "regenerate".into();
            }),
            "methods[1].compact_states",
            "\"off\" or \"on\"",
        ),
        (
            "cpu-knob",
            Box::new(|c| c["methods"][0]["compaction"] = "scan".into()),
            "methods[0].compaction",
            "cpu has no knob",
        ),
        (
            "bad-knob",
            Box::new(|c| c["methods"][1]["compaction"] = "sort".into()),
            "methods[1].compaction",
            "\"off\", \"atomic\" or \"scan\"",
        ),
        (
            "bad-light-knob",
            Box::new(|c| c["methods"][0]["light_sampling"] = serde_json::json!(["area", "cone"])),
            "methods[0].light_sampling[1]",
            "\"area\" or \"solid-angle\"",
        ),
        (
            "bad-light-select",
            Box::new(|c| c["methods"][1]["light_select"] = "powr".into()),
            "methods[1].light_select",
            "did you mean \"power\"",
        ),
        (
            "same-label",
            Box::new(|c| c["methods"][1] = serde_json::json!({"method": "cpu"})),
            "methods[1]",
            "used twice",
        ),
        ("same-seed", Box::new(|c| c["reference"]["seed"] = 0.into()), "reference.seed", "hide their error"),
        (
            "no-scene",
            Box::new(|c| c["scenes"] = serde_json::json!(["three-sphere"])),
            "scenes[0]",
            "did you mean \"three-spheres\"",
        ),
        (
            "no-exr",
            Box::new(|c| c["reference"] = serde_json::json!({"exr": "refs/{scene}.exr"})),
            "reference.exr",
            "three-spheres",
        ),
        ("trim", Box::new(|c| c["metrics"] = serde_json::json!({"trim": 1.5})), "metrics.trim", "[0, 1)"),
        ("warmup", Box::new(|c| c["warmup"] = (-1).into()), "warmup", "whole number"),
        (
            "warmup-agree",
            Box::new(|c| c["warmup"] = serde_json::json!({"agree": -0.1})),
            "warmup.agree",
            "must be in [0, 10]",
        ),
        (
            "warmup-field",
            Box::new(|c| c["warmup"] = serde_json::json!({"min_second": 1})),
            "warmup.min_second",
            "did you mean \"min_seconds\"",
        ),
        ("interleave", Box::new(|c| c["interleave"] = 1.into()), "interleave", "true or false"),
        (
            "preheat-seconds",
            Box::new(|c| c["preheat_seconds"] = 11.into()),
            "preheat_seconds",
            "must be in [0, 10]",
        ),
        (
            "unstable-spread",
            Box::new(|c| c["unstable_spread"] = "5%".into()),
            "unstable_spread",
            "expected a number",
        ),
        (
            "compute-passes",
            Box::new(|c| {
                c["methods"] = serde_json::json!([{"method": "wavefront", "compute_passes": "one"}])
            }),
            "methods[0].compute_passes",
            "\"per-dispatch\"",
        ),
    ];
    for (name, edit, field, reason) in cases {
        let mut c = good.clone();
        edit(&mut c);
        let path = write_config(&dir, name, &c);
        let e = ExperimentConfig::from_file(&path).expect_err(name);
        assert_eq!(e.file, path.display().to_string(), "{name}");
        assert_eq!(e.path, field, "{name}: {e}");
        assert!(e.reason.contains(reason), "{name}: {e}");
    }
    let dup = dir.join("dup.json");
    std::fs::write(&dup, r#"{"schema": "wavetrace-experiment/1", "spp": [1], "spp": [2]}"#).unwrap();
    let e = ExperimentConfig::from_file(&dup).unwrap_err();
    assert!(e.path == "spp" && e.reason.contains("only once"), "{e}");

    // Through the CLI: a clear message, no panic, nothing written.
    let bad = dir.join("spp-zero.json");
    let out = dir.join("never");
    let o = wavetrace(&["experiment", "run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && stderr.contains("spp-zero.json: spp[1]: must be in"), "{stderr}");
    assert!(!out.exists(), "a bad config renders nothing and writes nothing");
}

#[test]
fn every_shipped_config_is_valid_and_says_what_it_asks() {
    let dir = crate::common::root().join("experiments");
    let mut names = Vec::new();
    let device = std::fs::read_dir(dir.join("device")).unwrap().flatten();
    for entry in std::fs::read_dir(&dir).unwrap().flatten().chain(device) {
        let path = entry.path();
        let name = path.strip_prefix(&dir).unwrap().to_string_lossy().into_owned();
        if path.extension().is_none_or(|e| e != "json") || name == "report.schema.json" {
            continue;
        }
        let config = ExperimentConfig::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(config.question.len() > 20, "{name}: say what question it answers");
        assert!(!plan(&config).is_empty());
        if name.starts_with("device/") {
            // The device run renders nothing on the CPU (scripts/device_figures.sh).
            let raw = std::fs::read_to_string(&path).unwrap();
            assert!(!raw.contains("\"cpu"), "{name}: a CPU method or reference in a device config");
        }
        names.push(name);
    }
    names.sort();
    assert_eq!(
        names,
        [
            "baselines.json",
            "bvh_layouts.json",
            "bvh_stack.json",
            "coherence.json",
            "compute_passes.json",
            "cpu_vs_gpu.json",
            "decomposition.json",
            "device/bvh_layouts.json",
            "device/bvh_stack.json",
            "device/compute_passes.json",
            "device/decomposition.json",
            "device/fixed_costs.json",
            "device/headline.json",
            "device/material_kinds.json",
            "device/megakernel_threads.json",
            "device/pool_size.json",
            "device/queue_order.json",
            "device/refill.json",
            "device/regeneration_1080p.json",
            "device/regeneration_recheck.json",
            "device/roulette.json",
            "device/scene_size.json",
            "device/seeds_1080p.json",
            "device/shader_checks.json",
            "device/shading_cost.json",
            "device/simd.json",
            "device/specialize.json",
            "device/warmup.json",
            "dispatch_counts.json",
            "fresnel.json",
            "light_sampling.json",
            "material_cost.json",
            "material_kinds.json",
            "megakernel_vs_wavefront.json",
            "my_scene.json",
            "nee.json",
            "pool_memory.json",
            "precision.json",
            "queue_order.json",
            "quick.json",
            "ray_sort.json",
            "refill.json",
            "refill_1080p.json",
            "regeneration.json",
            "regeneration_1080p.json",
            "roulette.json",
            "scene_scale.json",
            "scene_size.json",
            "shader_checks.json",
            "specialize.json",
            "speed_vs_accuracy.json",
            "stability_distance.json",
            "stability_scale.json",
            "state_traffic.json",
            "triangles_10m.json",
            "wide_collapse.json",
            "workgroup_size.json"
        ]
    );
    let o = wavetrace(&[
        "experiment",
        "run",
        dir.join("quick.json").to_str().unwrap(),
        "--list",
        "--shard",
        "1/4",
    ]);
    assert!(o.status.success());
    let listed = String::from_utf8_lossy(&o.stdout);
    let config = ExperimentConfig::from_file(&dir.join("quick.json")).unwrap();
    assert_eq!(listed.lines().count(), plan(&config).iter().filter(|r| r.index % 4 == 1).count());
}

#[test]
fn a_sweep_over_scenes_gets_a_time_by_scene_chart() {
    let dir = scratch("by-scene");
    let config = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres", "furnace"],
        "resolutions": ["16x9"],
        "spp": [1],
        "repetitions": 1,
        "warmup": 0,
        "methods": [{"method": "cpu"}, {"method": "cpu-f64"}]
    });
    let config = ExperimentConfig::from_file(&write_config(&dir, "by-scene", &config)).unwrap();
    let opts = RunnerOptions {
        out_dir: dir.join("out"),
        shard: None,
        cache_dir: dir.join("cache"),
        resume: Resume::Off,
    };
    let report = runner::run(&config, &opts).unwrap();
    assert_valid(&dir.join("out"));
    let chart = report.charts.iter().find(|c| c.kind == "time-by-scene").expect("a time-by-scene chart");
    let svg = std::fs::read_to_string(dir.join("out").join(&chart.file)).unwrap();
    for name in ["three-spheres", "furnace", "cpu-f64"] {
        assert!(svg.contains(name), "{name} missing from the chart");
    }
    // No reference: no error metrics, no error-vs-time chart, and nothing pretends otherwise.
    assert!(report.runs.iter().all(|r| r.error_metrics.is_none() && r.efficiency.is_none()));
    assert!(report.charts.iter().all(|c| c.kind != "error-vs-time"));
}

#[test]
fn shard_arguments_are_checked() {
    assert_eq!("2/5".parse::<Shard>(), Ok(Shard { index: 2, count: 5 }));
    assert!("5/5".parse::<Shard>().unwrap_err().contains("0 <= I < N"));
    assert!("1/0".parse::<Shard>().is_err());
    assert!("x".parse::<Shard>().unwrap_err().contains("I/N"));
}

/// The light-sampling knobs are every method's: swept on the CPU and set on a GPU method, they
/// make variants labelled by value, reach each run's options (and so runs.csv's columns), and the
/// report still validates. The variants are unbiased estimators of one image: each agrees with
/// the reference and with the others within their noise (`mean_difference_z`, whose power is
/// shown by `a_biased_light_variant_fails_the_agreement_check`).
#[test]
fn light_knobs_sweep_on_every_method_and_reach_the_records() {
    let dir = scratch("light-knobs");
    let (report, images, reference) = light_variants(&dir);
    let options: Vec<(String, String)> = report
        .runs
        .iter()
        .map(|r| {
            (
                r.options["light_sampling"].as_str().unwrap().into(),
                r.options["light_select"].as_str().unwrap().into(),
            )
        })
        .collect();
    let want = [("area", "power"), ("solid-angle", "power"), ("solid-angle", "uniform")];
    assert_eq!(options, want.map(|(a, b)| (a.to_string(), b.to_string())));
    let csv = std::fs::read_to_string(dir.join("out").join("runs.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.contains(",light_sampling,light_select,"), "{header}");
    let mask = bulb_mask(&reference);
    for (i, a) in images.iter().enumerate() {
        let z = mean_difference_z(a, &reference, &mask);
        eprintln!("{} vs reference: z = {z:.2}", report.runs[i].label);
        assert!(z.abs() <= AGREE_Z, "{} vs the reference: z = {z:.2}", report.runs[i].label);
        for (j, b) in images.iter().enumerate().skip(i + 1) {
            let z = mean_difference_z(a, b, &mask);
            let (la, lb) = (&report.runs[i].label, &report.runs[j].label);
            eprintln!("{la} vs {lb}: z = {z:.2}");
            assert!(z.abs() <= AGREE_Z, "{la} vs {lb}: z = {z:.2}");
        }
    }
}

/// The negative control of the check above, on the same renders: a light variant 2% too bright
/// or too dark fails against the variant it traces the same paths as (the solid-angle variants
/// differ only in which light they pick, so their noise largely cancels: measured z of ±6.6 to
/// ±8.2 for ±2%), and one 10% off fails against the independent reference (whose noise at these
/// sample counts hides a few percent: a 2% bias moves z by about 1.4). Each check itself passes
/// unbiased (previous test).
#[test]
fn a_biased_light_variant_fails_the_agreement_check() {
    let dir = scratch("light-knobs-biased");
    let (_, images, reference) = light_variants(&dir);
    let mask = bulb_mask(&reference);
    let scaled =
        |img: &RgbImage, f: f32| RgbImage { data: img.data.iter().map(|v| v * f).collect(), ..img.clone() };
    for f in [1.02, 0.98] {
        let z = mean_difference_z(&scaled(&images[1], f), &images[2], &mask);
        assert!(z.abs() > AGREE_Z, "solid-angle ×{f} vs uniform selection passed: z = {z:.2}");
    }
    for f in [1.1, 0.9] {
        for (i, img) in images.iter().enumerate() {
            let z = mean_difference_z(&scaled(img, f), &reference, &mask);
            assert!(z.abs() > AGREE_Z, "variant {i} ×{f} vs the reference passed: z = {z:.2}");
        }
    }
}

/// Two images estimate the same one: |z| of their mean difference at most this. The renders are
/// seeded, so the outcome is fixed for a build; 4 leaves room for the heavy tails of small-light
/// sampling.
const AGREE_Z: f64 = 4.0;

/// The two-lights light variants (area vs solid-angle sampling of the bulb; power vs uniform
/// light selection, in f64) at 40x24 and 256 spp with NEE, against a 2048-spp `cpu-f64`
/// reference: the report, each run's image and the reference image.
fn light_variants(dir: &Path) -> (ExperimentReport, Vec<RgbImage>, RgbImage) {
    let mut config = small_config(serde_json::json!([
        {"method": "cpu", "light_sampling": ["area", "solid-angle"]},
        {"method": "cpu-f64", "light_select": "uniform"},
    ]));
    config["scenes"] = serde_json::json!(["two-lights"]);
    config["nee"] = serde_json::json!([true]);
    config["spp"] = serde_json::json!([256]);
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"]["spp"] = 2048.into();
    let config = ExperimentConfig::from_file(&write_config(dir, "light-knobs", &config)).unwrap();
    let labels: Vec<&str> = config.methods.iter().map(|m| m.label.as_str()).collect();
    assert_eq!(
        labels,
        ["cpu light-sampling=area", "cpu light-sampling=solid-angle", "cpu-f64 light-select=uniform"]
    );
    let opts = RunnerOptions {
        out_dir: dir.join("out"),
        shard: None,
        cache_dir: dir.join("cache"),
        resume: Resume::Off,
    };
    let report = runner::run(&config, &opts).unwrap();
    assert_valid(&dir.join("out"));
    let images = report
        .runs
        .iter()
        .map(|r| read_exr(dir.join("out").join(&r.images.as_ref().unwrap().exr)).unwrap().0)
        .collect();
    let reference = read_exr(&report.references[0].exr).unwrap().0;
    (report, images, reference)
}

/// Pixels that see the bulb (radiance 100) directly, with their neighbours: left out of
/// [`mean_difference_z`], where how much of a pixel the bulb covers, the same in every light
/// variant, would drown what light sampling changes.
fn bulb_mask(reference: &RgbImage) -> Vec<bool> {
    let (w, h) = (reference.width as i64, reference.height as i64);
    let bright = |x: i64, y: i64| {
        (0..w).contains(&x)
            && (0..h).contains(&y)
            && reference.get(x as u32, y as u32).iter().sum::<f32>() / 3.0 > 2.0
    };
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| (-1..=1).any(|dy| (-1..=1).any(|dx| bright(x + dx, y + dy))))
        .collect()
}

/// z of the mean per-pixel difference (channels averaged) of `a` and `b` over the unmasked
/// pixels: pixels are independent (each its own random stream), so the spread of their
/// differences measures the noise of the mean, whether or not `a` and `b` trace the same paths.
fn mean_difference_z(a: &RgbImage, b: &RgbImage, mask: &[bool]) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let d: Vec<f64> = (0..a.data.len() / 3)
        .filter(|&i| !mask[i])
        .map(|i| {
            (0..3).map(|c| f64::from(a.data[3 * i + c]) - f64::from(b.data[3 * i + c])).sum::<f64>() / 3.0
        })
        .collect();
    let n = d.len() as f64;
    assert!(n > 100.0, "too few pixels left: {n}");
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    mean / (var / n).sqrt()
}

/// The numerical knobs and stress transforms are every method's: single values and sweeps become
/// variants labelled by value (a three-number `translate` is one vector), and the reference takes
/// the numerical knobs and `"spp": "match"`.
#[test]
fn numerical_knobs_and_stress_transforms_parse_into_labelled_variants() {
    use wavetrace::experiment::config::{ReferenceSamples, ReferenceSpec};
    use wavetrace::numerics::{Fresnel, RayOffset, SphereHit};

    let dir = scratch("numeric-knobs");
    let mut config = small_config(serde_json::json!([
        {"method": "cpu", "scale": [1, 1e-4, 1e4]},
        {"method": "cpu-f64", "translate": [0, 1e5, [1, 2, 3]]},
        {"method": "megakernel", "translate": [1, 2, 3]},
        {"method": "wavefront", "ray_offset": ["tmin", "tmin=1e-4", "robust"], "sphere_hit": "book", "fresnel": "exact"},
        {"method": "cpu", "label": "far", "translate": [[0], [1e3], [1e5]]},
        {"method": "cpu", "label": "plain", "scale": 2, "fresnel": "exact"}
    ]));
    config["reference"] = serde_json::json!({"method": "cpu-f64", "spp": "match", "fresnel": "exact", "ray_offset": "robust", "sphere_hit": "book"});
    let config = ExperimentConfig::from_file(&write_config(&dir, "knobs", &config)).unwrap();
    let labels: Vec<&str> = config.methods.iter().map(|m| m.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "cpu scale=1",
            "cpu scale=1e-4",
            "cpu scale=1e4",
            "cpu-f64 translate=0",
            "cpu-f64 translate=1e5",
            "cpu-f64 translate=1,2,3",
            "megakernel translate=1,2,3",
            "wavefront ray-offset=tmin sphere-hit=book fresnel=exact",
            "wavefront ray-offset=tmin=1e-4 sphere-hit=book fresnel=exact",
            "wavefront ray-offset=robust sphere-hit=book fresnel=exact",
            "far translate=0",
            "far translate=1e3",
            "far translate=1e5",
            "plain",
        ]
    );
    let o = |i: usize| &config.methods[i].options;
    assert_eq!([o(0).stress.scale, o(1).stress.scale, o(2).stress.scale], [1.0, 1e-4, 1e4]);
    assert_eq!(o(4).stress.translate, [1e5; 3]);
    assert_eq!(o(5).stress.translate, [1.0, 2.0, 3.0]);
    assert_eq!(o(6).stress.translate, [1.0, 2.0, 3.0], "three numbers are one vector");
    assert_eq!(o(8).numerics.ray_offset, RayOffset::Tmin(1e-4));
    assert_eq!(o(9).numerics.ray_offset, RayOffset::Robust);
    assert!((7..10)
        .all(|i| o(i).numerics.sphere_hit == SphereHit::Book && o(i).numerics.fresnel == Fresnel::Exact));
    assert_eq!(o(12).stress.translate, [1e5; 3]);
    assert_eq!((o(13).stress.scale, o(13).numerics.fresnel), (2.0, Fresnel::Exact));
    match &config.reference {
        Some(ReferenceSpec::Render { samples: ReferenceSamples::Match, numerics, .. }) => {
            assert_eq!(
                (numerics.ray_offset, numerics.sphere_hit, numerics.fresnel),
                (RayOffset::Robust, SphereHit::Book, Fresnel::Exact)
            );
        }
        other => panic!("{other:?}"),
    }
    // A matched reference is each run's own settings and light knobs, never its transform.
    let run = config.settings().next().unwrap();
    let (_, settings, options) =
        config.reference.as_ref().unwrap().render_for(&run, &config.methods[2].options).unwrap();
    assert_eq!(settings, run);
    assert!(options.stress.is_identity());
}

/// Each bad numerical knob, stress transform or reference field is refused with the file, the
/// JSON path and the reason.
#[test]
fn bad_numerical_knobs_and_stress_transforms_are_refused() {
    let dir = scratch("bad-numeric");
    let good = small_config(serde_json::json!([{"method": "cpu"}, {"method": "wavefront"}]));
    type Case = (&'static str, Box<dyn Fn(&mut Value)>, &'static str, &'static str);
    let knob = |k: &'static str, v: Value| -> Box<dyn Fn(&mut Value)> {
        Box::new(move |c| c["methods"][0][k] = v.clone())
    };
    let reference = |k: &'static str, v: Value| -> Box<dyn Fn(&mut Value)> {
        Box::new(move |c| c["reference"][k] = v.clone())
    };
    use serde_json::json;
    let cases: Vec<Case> = vec![
        (
            "scale-zero",
            knob("scale", json!(0)),
            "methods[0].scale",
            "scale must be a finite number > 0, found 0",
        ),
        ("scale-negative", knob("scale", json!(-2)), "methods[0].scale", "> 0, found -2"),
        ("scale-nan", knob("scale", json!("nan")), "methods[0].scale", "expected a number > 0"),
        ("scale-in-sweep", knob("scale", json!([1, 0])), "methods[0].scale[1]", "> 0"),
        ("scale-f32", knob("scale", json!(1e39)), "methods[0].scale", "outside f32's range"),
        ("scale-repeat", knob("scale", json!([1, 1.0])), "methods[0].scale[1]", "repeats"),
        ("scale-overflows-scene", knob("scale", json!(1e37)), "methods[0].scale", "scene \"three-spheres\""),
        ("translate-f32", knob("translate", json!(1e39)), "methods[0].translate", "overflows f32"),
        (
            "translate-vector-f32",
            knob("translate", json!([0, 1e39, 0])),
            "methods[0].translate",
            "translate y",
        ),
        (
            "translate-in-sweep",
            knob("translate", json!([0, [1e39]])),
            "methods[0].translate[1]",
            "overflows f32",
        ),
        ("translate-two", knob("translate", json!([0, [1, 2]])), "methods[0].translate[1]", "[x, y, z]"),
        ("translate-string", knob("translate", json!("far")), "methods[0].translate", "[[a], [b], [c]]"),
        (
            "translate-element",
            knob("translate", json!([[1, "a", 3]])),
            "methods[0].translate[0]",
            "a number D",
        ),
        ("tmin-negative", knob("ray_offset", json!("tmin=-1")), "methods[0].ray_offset", "≥ 0, found -1"),
        (
            "ray-offset-name",
            knob("ray_offset", json!(["robust", "epsilon"])),
            "methods[0].ray_offset[1]",
            "\"robust\"",
        ),
        ("ray-offset-number", knob("ray_offset", json!(0.001)), "methods[0].ray_offset", "expected a string"),
        ("sphere-hit", knob("sphere_hit", json!("fast")), "methods[0].sphere_hit", "\"book\" or \"stable\""),
        ("fresnel", knob("fresnel", json!("exakt")), "methods[0].fresnel", "did you mean \"exact\""),
        ("reference-scale", reference("scale", json!(2)), "reference.scale", "untransformed scene"),
        (
            "reference-translate",
            reference("translate", json!(1)),
            "reference.translate",
            "untransformed scene",
        ),
        ("reference-spp", reference("spp", json!("matched")), "reference.spp", "or \"match\""),
        (
            "reference-match-seed",
            Box::new(|c| c["reference"] = json!({"method": "cpu-f64", "spp": "match", "seed": 3})),
            "reference.seed",
            "each run's own",
        ),
        (
            "reference-match-depth",
            Box::new(|c| c["reference"] = json!({"method": "cpu-f64", "spp": "match", "max_depth": 3})),
            "reference.max_depth",
            "each run's own",
        ),
        (
            "reference-fresnel",
            reference("fresnel", json!("exakt")),
            "reference.fresnel",
            "did you mean \"exact\"",
        ),
        ("reference-tmin", reference("ray_offset", json!("tmin=-1")), "reference.ray_offset", "≥ 0"),
        (
            "reference-light",
            reference("light_sampling", json!("area")),
            "reference.light_sampling",
            "unknown field",
        ),
    ];
    for (name, edit, field, reason) in cases {
        let mut c = good.clone();
        edit(&mut c);
        let path = write_config(&dir, name, &c);
        let e = ExperimentConfig::from_file(&path).expect_err(name);
        assert_eq!(e.file, path.display().to_string(), "{name}");
        assert_eq!(e.path, field, "{name}: {e}");
        assert!(e.reason.contains(reason), "{name}: {e}");
    }
}

/// A scale sweep on the CPU against a matched reference: one reference per spp at the runs' own
/// seed, the failure counters in every record, runs.csv and the page, and stability and
/// error-vs-spp charts drawn from report.json.
#[test]
fn a_scale_sweep_against_a_matched_reference_reports_counters_and_stability_charts() {
    let dir = scratch("stability");
    let config = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres"],
        "resolutions": ["8x8"],
        "spp": [1, 4],
        "max_depth": [8],
        "repetitions": 1,
        "warmup": 0,
        "methods": [
            {"method": "cpu", "scale": [1e-3, 1, 1e3]},
            {"method": "cpu", "label": "far", "translate": [0, 1e4]}
        ],
        "reference": {"method": "cpu-f64", "spp": "match", "fresnel": "schlick"}
    });
    let path = write_config(&dir, "stability", &config);
    let out = dir.join("out");
    let cache = dir.join("cache");
    let o = run_experiment(&path, &out, &cache);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_valid(&out);
    let (header, _) = crate::tidy::assert_tidy(&out);
    let header = header.join(",");
    assert!(header.contains(",threads,ray_offset,sphere_hit,fresnel,scale,translate,"), "{header}");
    assert!(header.contains(",invalid_samples,self_hits,shadow_self_hits,depth_cut,"), "{header}");

    let report = ExperimentReport::read(&out).unwrap();
    assert_eq!(report.runs.len(), 10);
    for r in &report.runs {
        assert_eq!(r.status, RunStatus::Ok, "{}: {:?}", r.id, r.error);
        assert!(r.self_hits.is_some() && r.shadow_self_hits.is_some() && r.depth_cut.is_some(), "{}", r.id);
        for k in ["ray_offset", "sphere_hit", "fresnel", "scale", "translate"] {
            assert!(!r.options[k].is_null(), "{}: no {k}", r.id);
        }
        // Its reference: the untransformed scene at the run's own spp and seed.
        let key = r.reference.as_ref().unwrap();
        let reference = report.references.iter().find(|x| &x.key == key).unwrap();
        assert!(reference.spp_match);
        assert_eq!(
            (reference.spp, reference.seed, reference.max_depth),
            (Some(r.spp), Some(r.seed), Some(8))
        );
        assert_eq!(reference.options.as_ref().unwrap()["fresnel"], "schlick");
        assert!(r.error_metrics.as_ref().unwrap().relmse.is_finite());
    }
    assert_eq!(report.runs[1].options["scale"], 1.0);
    assert_eq!(report.runs[2].options["scale"], 1e3);
    assert_eq!(report.runs[4].options["translate"], serde_json::json!([1e4, 1e4, 1e4]));
    // One reference per spp, shared by every variant: cached per spp.
    assert_eq!(report.references.len(), 2);
    assert!(report.references.iter().all(|r| !r.cached));
    // Same random numbers: the unscaled f32 run differs from its f64 twin by far less than noise.
    let unscaled = |spp: u32| {
        let r = report.runs.iter().find(|r| r.label == "cpu scale=1" && r.spp == spp).unwrap();
        r.error_metrics.as_ref().unwrap().relmse
    };
    assert!(unscaled(1) < 1e-2 && unscaled(4) < 1e-2, "{} {}", unscaled(1), unscaled(4));

    // The charts.
    let files: Vec<&str> = report.charts.iter().map(|c| c.file.as_str()).collect();
    for want in [
        "charts/error-vs-spp-three-spheres-8x8.svg",
        "charts/stability-scale-three-spheres-8x8.svg",
        "charts/stability-scale-self-hits-three-spheres-8x8.svg",
        "charts/stability-translate-three-spheres-8x8.svg",
        "charts/stability-translate-self-hits-three-spheres-8x8.svg",
    ] {
        assert!(files.contains(&want), "no {want} in {files:?}");
    }
    let svg = |f: &str| std::fs::read_to_string(out.join(f)).unwrap();
    let scale = svg("charts/stability-scale-three-spheres-8x8.svg");
    // One line for the swept variant, its scale gone from the name; spp tells lines apart.
    assert!(scale.contains("\ncpu 1spp\n") && scale.contains("\ncpu 4spp\n"), "{scale}");
    assert!(!scale.contains("cpu scale="), "{scale}");
    let hits = svg("charts/stability-scale-self-hits-three-spheres-8x8.svg");
    assert!(
        hits.contains("secondary + shadow self-hits + 1, per render") && hits.contains("none drawn at 1"),
        "{hits}"
    );
    let translate = svg("charts/stability-translate-three-spheres-8x8.svg");
    assert!(
        translate.contains("0 drawn at the tick marked 0") && translate.contains("\nfar 1spp\n"),
        "{translate}"
    );
    assert!(report.charts.iter().filter(|c| c.kind == "stability").count() == 4);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for want in ["<th>self-hits</th>", "<th>shadow self-hits</th>", "<th>depth-cut</th>", "the run's seed"] {
        assert!(html.contains(want), "no {want} in the page");
    }

    // A rerun takes both references from the cache.
    let again = dir.join("again");
    let o = run_experiment(&path, &again, &cache);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let second = ExperimentReport::read(&again).unwrap();
    assert!(second.references.len() == 2 && second.references.iter().all(|r| r.cached));

    // A report from before the knobs and counters existed still reads and draws.
    let mut old: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    for r in old["runs"].as_array_mut().unwrap() {
        let r = r.as_object_mut().unwrap();
        for k in ["self_hits", "shadow_self_hits", "depth_cut"] {
            r.remove(k);
        }
        let options = r["options"].as_object_mut().unwrap();
        for k in ["ray_offset", "sphere_hit", "fresnel", "scale", "translate"] {
            options.remove(k);
        }
    }
    for r in old["references"].as_array_mut().unwrap() {
        r.as_object_mut().unwrap().remove("options");
        r.as_object_mut().unwrap().remove("spp_match");
    }
    std::fs::write(again.join("report.json"), serde_json::to_string(&old).unwrap()).unwrap();
    let o = wavetrace(&["experiment", "report", again.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let redrawn = ExperimentReport::read(&again).unwrap();
    assert!(redrawn.runs.iter().all(|r| r.self_hits.is_none()));
    assert!(
        redrawn.charts.iter().all(|c| c.kind != "stability"),
        "no transform recorded: no stability chart"
    );
}

/// The committed results (reports written before later fields existed) still read, and every
/// chart they list is drawn from them still.
#[test]
fn committed_reports_still_read_and_draw() {
    let root = crate::common::root().join("experiments/results");
    let mut dirs = vec![root];
    let mut read = 0;
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.file_name().is_some_and(|n| n == "report.json") {
                let report = ExperimentReport::read(path.parent().unwrap())
                    .unwrap_or_else(|e| panic!("{}: {e:#}", path.display()));
                let charts = wavetrace::experiment::charts::charts(&report);
                for c in &charts {
                    assert!(
                        c.svg.contains("<svg") && !c.svg.contains("NaN"),
                        "{}: {}",
                        path.display(),
                        c.stem
                    );
                }
                // Every chart drawn when the report was made is drawn still (crossover included).
                let now: Vec<String> = charts.iter().map(|c| format!("charts/{}.svg", c.stem)).collect();
                for before in &report.charts {
                    assert!(
                        now.contains(&before.file),
                        "{}: {} is no longer drawn",
                        path.display(),
                        before.file
                    );
                }
                read += 1;
            }
        }
    }
    assert!(read > 0, "no committed report found");
}

/// Every run records what ran, not what was asked (issue 45): a knob that resolves at run time
/// (`schedule`, `queue_order`, `scan`, `append`, the pool, the persistent threads) is never
/// recorded as `auto` or left empty, in report.json and in `render --report` (the block of the
/// method that ran) alike.
#[test]
fn reports_record_every_knob_as_it_ran() {
    if crate::common::gpu().is_none() {
        return;
    }
    fn autos(v: &Value, path: &str, out: &mut Vec<String>) {
        match v {
            Value::String(s) if s == "auto" => out.push(path.to_string()),
            Value::Object(m) => m.iter().for_each(|(k, v)| autos(v, &format!("{path}.{k}"), out)),
            _ => {}
        }
    }
    let dir = scratch("resolved");
    let mut config = small_config(serde_json::json!([
        {"method": "megakernel"},
        {"method": "megakernel", "label": "regenerating", "schedule": "regenerate"},
        {"method": "wavefront"},
        {"method": "wavefront", "label": "wf-regenerate", "schedule": "regenerate", "tail": "megakernel"}
    ]));
    config["spp"] = serde_json::json!([2]);
    config.as_object_mut().unwrap().remove("reference");
    let path = write_config(&dir, "resolved", &config);
    let out = dir.join("out");
    let o = run_experiment(&path, &out, &dir.join("cache"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = assert_valid(&out);
    for run in report["runs"].as_array().unwrap() {
        let (label, options) = (run["label"].as_str().unwrap(), &run["options"]);
        let mut found = Vec::new();
        autos(options, label, &mut found);
        assert!(found.is_empty(), "recorded as auto: {found:?}");
        if run["method"] == "wavefront" {
            assert!(options["pool_size"].as_u64().is_some_and(|p| p > 0), "{label}: {options}");
            assert!(options["schedule"] == "waves" || options["schedule"] == "regenerate", "{label}");
        }
        if label == "regenerating" {
            assert!(options["threads"].as_u64().is_some_and(|t| t > 0), "{label}: {options}");
        }
    }
    let json = dir.join("render.json");
    let o = wavetrace(&[
        "render",
        "--scene",
        "three-spheres",
        "--method",
        "wavefront",
        "--width",
        "16",
        "--height",
        "8",
        "--spp",
        "1",
        "--warmup",
        "0",
        "--out",
        dir.join("render.exr").to_str().unwrap(),
        "--report",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // The run report holds both GPU methods' blocks; the megakernel's is as asked (it did not run).
    let mut options = r["options"].clone();
    options.as_object_mut().unwrap().remove("megakernel");
    let mut found = Vec::new();
    autos(&options, "render", &mut found);
    assert!(found.is_empty(), "render --report recorded as auto: {found:?}");
    assert!(r["options"]["wavefront"]["pool_size"].as_u64().is_some(), "{}", r["options"]);
}

/// `experiment run --set KEY=VALUE` changes the config without copying it: the runs planned
/// follow, the report records the overrides beside the effective config, and a bad override
/// gets the file, the field and the reason, naming the `--set` that caused it.
#[test]
fn set_overrides_the_config_and_is_recorded() {
    let dir = scratch("set");
    let config = small_config(serde_json::json!([{"method": "cpu"}, {"method": "cpu-f64"}]));
    let path = write_config(&dir, "set", &config);
    let p = path.to_str().unwrap();
    let list = |extra: &[&str]| {
        let mut args = vec!["experiment", "run", p, "--list"];
        args.extend_from_slice(extra);
        wavetrace(&args)
    };
    let all = String::from_utf8_lossy(&list(&[]).stdout).lines().count();
    let o = list(&["--set", "spp=[2]"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count() * 2, all, "one of two spp values");
    let o = list(&["--set", "spp=[2]", "--set", "methods.1.method=cpu"]);
    assert!(!o.status.success(), "two variants labelled cpu");
    for (set, parts) in [
        ("spp=[0]", vec!["set.json", "spp", "(set by --set spp=[0])"]),
        ("spq=[2]", vec!["set.json", "spq", "did you mean \"spp\"", "(set by --set spq=[2])"]),
        ("methods.5.label=x", vec!["set.json", "--set methods.5.label=x", "has 2 entries"]),
        ("spp", vec!["KEY=VALUE"]),
    ] {
        let o = list(&["--set", set]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && !stderr.contains("panicked"), "{set}: {stderr}");
        for part in parts {
            assert!(stderr.contains(part), "{set}: {part:?} not in {stderr}");
        }
    }
    let out = dir.join("out");
    let set = ["--set", "spp=[2]", "--set", "methods.1.label=reference-f64"];
    let o = run_experiment_with(&path, &out, &dir.join("cache"), &set);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = assert_valid(&out);
    assert_eq!(report["overrides"], serde_json::json!(["spp=[2]", "methods.1.label=reference-f64"]));
    assert_eq!(report["config"]["spp"], serde_json::json!([2]));
    assert_eq!(report["runs"].as_array().unwrap().len(), 2);
    assert!(report["runs"].as_array().unwrap().iter().any(|r| r["label"] == "reference-f64"));
}
