//! Command-line paths no other test ran (issue 29): every render flag through the binary and
//! into the report and the EXR, `experiment merge|report|run` errors and exit statuses,
//! `compare` options and errors, `scene list`, `info`, unwritable outputs. Tiny renders.

use crate::common;
use crate::experiment::{assert_valid, scratch, small_config, wavetrace, write_config};

use std::path::Path;
use std::process::Output;

fn ok(args: &[&str]) -> Output {
    let out = wavetrace(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// Runs and expects failure, without a panic, with a message containing every one of `needles`.
fn fails_with(args: &[&str], needles: &[&str]) -> String {
    let out = wavetrace(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: stderr lacks {n:?}:\n{stderr}");
    }
    stderr
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A two-run config (one CPU method, two spp) with a cheap reference, written into `dir`.
fn two_run_config(dir: &Path) -> std::path::PathBuf {
    let mut config = small_config(serde_json::json!([{"method": "cpu"}]));
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"] = serde_json::json!({"method": "cpu", "spp": 4});
    write_config(dir, "two-runs", &config)
}

/// `experiment merge` from the command line: an incomplete merge writes its report but exits
/// non-zero naming the missing runs (a job script must not go on), `--allow-incomplete` accepts
/// it, all shards merge with exit 0, and bad arguments are clear errors.
#[test]
fn experiment_merge_exit_status_and_errors() {
    let dir = scratch("cli-merge");
    let config = two_run_config(&dir);
    let cache = dir.join("cache");
    for i in 0..2 {
        let shard = dir.join(format!("shard{i}"));
        let index = format!("{i}/2");
        ok(&["experiment", "run", s(&config), "--out", s(&shard), "--cache", s(&cache), "--shard", &index]);
    }
    let (a, b) = (dir.join("shard0"), dir.join("shard1"));
    let partial = dir.join("partial");
    let err = fails_with(
        &["experiment", "merge", s(&a), "--out", s(&partial)],
        &["incomplete", "1 of 2 runs", "[1]", "--allow-incomplete"],
    );
    assert!(!err.contains("[0]"), "run 0 is there: {err}");
    assert_eq!(assert_valid(&partial)["status"], "incomplete", "the report is still written");
    let accepted = dir.join("accepted");
    ok(&["experiment", "merge", s(&a), "--out", s(&accepted), "--allow-incomplete"]);
    assert_eq!(assert_valid(&accepted)["missing_runs"], serde_json::json!([1]));
    let merged = dir.join("merged");
    ok(&["experiment", "merge", s(&a), s(&b), "--out", s(&merged)]);
    let report = assert_valid(&merged);
    assert_eq!(report["status"], "complete");
    assert_eq!(report["runs"].as_array().unwrap().len(), 2);
    fails_with(&["experiment", "merge", s(&a)], &["--out"]);
    fails_with(&["experiment", "merge", "--out", s(&merged)], &["DIRS"]);
    let nowhere = dir.join("no-such-shard");
    fails_with(&["experiment", "merge", s(&nowhere), "--out", s(&merged)], &["no-such-shard"]);
    fails_with(&["experiment", "merge", s(&a), s(&a), "--out", s(&dir.join("twice"))], &["in both"]);
}

#[test]
fn experiment_report_and_run_name_what_is_missing() {
    let dir = scratch("cli-missing");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    fails_with(&["experiment", "report", s(&empty)], &["empty", "report.json"]);
    fails_with(&["experiment", "run", s(&dir.join("nope.json"))], &["nope.json", "cannot read"]);
}

/// Every numerical and sampling flag reaches the report's settings and options and the EXR's
/// attributes; the seed changes the image and repeats it.
#[test]
fn render_flags_reach_the_report_and_the_exr() {
    let dir = scratch("cli-flags");
    let render = |name: &str, seed: &str| {
        let (exr, report) = (dir.join(format!("{name}.exr")), dir.join(format!("{name}.json")));
        ok(&[
            "render",
            "--scene",
            "three-spheres",
            "--method",
            "cpu",
            "--width",
            "12",
            "--height",
            "8",
            "--spp",
            "2",
            "--max-depth",
            "7",
            "--seed",
            seed,
            "--accel",
            "none",
            "--sphere-hit",
            "book",
            "--fresnel",
            "exact",
            "--nee",
            "on",
            "--roulette",
            "on",
            "--out",
            s(&exr),
            "--report",
            s(&report),
        ]);
        (wavetrace::image_io::read_exr(&exr).unwrap(), json(&report))
    };
    let ((img, attrs), r) = render("a", "7");
    let want = serde_json::json!({"width": 12, "height": 8, "spp": 2, "max_depth": 7, "seed": 7,
        "accel": "none", "nee": true, "roulette": true});
    assert_eq!(r["settings"], want);
    assert_eq!(r["options"]["sphere_hit"], "book");
    assert_eq!(r["options"]["fresnel"], "exact");
    let attr = |k: &str| attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()).unwrap_or_default();
    assert_eq!(attr("wavetrace.max_depth"), "7");
    assert_eq!(attr("wavetrace.seed"), "7");
    assert_eq!(attr("wavetrace.nee"), "on");
    // The rule, not just "on": pbrt-v4's.
    assert_eq!(attr("wavetrace.roulette"), "pbrt-v4");
    let commit = attr("wavetrace.git_commit");
    assert_eq!(commit, r["build"]["git_commit"].as_str().unwrap());
    assert!(commit.len() >= 40 || commit == "unknown", "a commit hash: {commit:?}");
    let ((again, _), _) = render("b", "7");
    assert_eq!(img.data, again.data, "one seed, one image");
    let ((other, _), _) = render("c", "8");
    assert_ne!(img.data, other.data, "another seed, other paths");
}

/// GPU flags: the megakernel's dispatch size and persistent threads, the wavefront's
/// compaction, sync interval, tail threshold and scan, and the timing mode reach the run.
#[test]
fn gpu_render_flags_reach_the_run() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("cli-gpu-flags");
    let render = |name: &str, extra: &[&str]| {
        let (exr, report) = (dir.join(format!("{name}.exr")), dir.join(format!("{name}.json")));
        let mut args = vec![
            "render",
            "--scene",
            "three-spheres",
            "--width",
            "16",
            "--height",
            "8",
            "--spp",
            "4",
            "--max-depth",
            "8",
            "--out",
            s(&exr),
            "--report",
            s(&report),
        ];
        args.extend_from_slice(extra);
        ok(&args);
        json(&report)
    };
    // 512 samples, 128 per dispatch: four megakernel dispatches, each with its accumulate pass.
    let r = render("mk", &["--method", "megakernel", "--samples-per-dispatch", "128", "--timing", "frame"]);
    assert_eq!(r["options"]["megakernel"]["samples_per_dispatch"], 128);
    assert_eq!(r["passes"]["megakernel"]["passes"], 4, "{}", r["passes"]);
    assert_eq!(r["dispatches"], 8);
    assert_eq!(r["options"]["timing"], "frame");
    assert_eq!(r["options"]["specialize"], "scene");
    assert!(r["frame_seconds"].as_f64().unwrap() > 0.0);
    let r = render(
        "regen",
        &["--method", "megakernel", "--schedule", "regenerate", "--threads", "64", "--specialize", "none"],
    );
    assert_eq!(r["options"]["megakernel"]["threads"], 64);
    assert_eq!(r["options"]["specialize"], "none");
    assert_eq!(r["options"]["megakernel"]["schedule"], "regenerate");
    let r = render(
        "wf",
        &[
            "--method",
            "wavefront",
            "--compaction",
            "off",
            "--schedule",
            "regenerate",
            "--sync-every",
            "3",
            "--tail",
            "megakernel",
            "--tail-threshold",
            "0.25",
            "--pool-size",
            "96",
        ],
    );
    let wf = &r["options"]["wavefront"];
    assert_eq!(wf["compaction"], "off");
    assert_eq!(wf["sync_every"], 3);
    assert_eq!(wf["tail"], "megakernel");
    assert_eq!(wf["tail_threshold"], 0.25);
    assert_eq!(r["pool_size"], 96);
    let r = render(
        "scan",
        &["--method", "wavefront", "--compaction-method", "scan", "--scan", "workgroup", "--pool-size", "96"],
    );
    assert_eq!(r["options"]["wavefront"]["compaction"], "scan");
    assert_eq!(r["options"]["wavefront"]["scan"], "workgroup");
    fails_with(
        &[
            "render",
            "--scene",
            "furnace",
            "--method",
            "wavefront",
            "--pool-size",
            "0",
            "--width",
            "4",
            "--height",
            "4",
            "--out",
            s(&dir.join("zero.exr")),
        ],
        &["--pool-size must be at least 1"],
    );
}

#[test]
fn unwritable_outputs_and_missing_inputs_are_clear_errors() {
    let dir = scratch("cli-unwritable");
    let exr = dir.join("x.exr");
    let base = [
        "render",
        "--scene",
        "furnace",
        "--method",
        "cpu",
        "--width",
        "4",
        "--height",
        "4",
        "--out",
        s(&exr),
    ];
    for flag in ["--png", "--report"] {
        let mut args = base.to_vec();
        args.extend_from_slice(&[flag, "/nonexistent-dir/x.out"]);
        fails_with(&args, &["/nonexistent-dir/x.out"]);
    }
    ok(&base);
    let missing = dir.join("missing.exr");
    fails_with(&["compare", s(&exr), s(&missing)], &["missing.exr"]);
    fails_with(&["compare", s(&missing), s(&exr)], &["missing.exr"]);
}

/// `compare --trim` drops the largest errors (outliers) and `--no-flip` leaves FLIP out.
#[test]
fn compare_trim_and_no_flip() {
    let dir = scratch("cli-compare");
    let render = |name: &str, spp: &str| {
        let exr = dir.join(name);
        ok(&[
            "render",
            "--scene",
            "three-spheres",
            "--method",
            "cpu",
            "--width",
            "20",
            "--height",
            "10",
            "--spp",
            spp,
            "--out",
            s(&exr),
        ]);
        exr
    };
    let (a, b) = (render("a.exr", "2"), render("b.exr", "16"));
    let metrics = |extra: &[&str]| {
        let mut args = vec!["compare", s(&a), s(&b), "--json"];
        args.extend_from_slice(extra);
        let r: serde_json::Value = serde_json::from_slice(&ok(&args).stdout).unwrap();
        r
    };
    let full = metrics(&[]);
    assert!(full["metrics"]["flip"].as_f64().is_some(), "FLIP by default: {full}");
    assert_eq!(full["metrics"]["trimmed_pixels"], 0);
    let trimmed = metrics(&["--trim", "0.1", "--no-flip"]);
    assert!(trimmed["metrics"]["flip"].is_null());
    assert_eq!(trimmed["trim"], 0.1);
    assert_eq!(trimmed["metrics"]["trimmed_pixels"], 20);
    let (f, t) = (full["metrics"]["mse"].as_f64().unwrap(), trimmed["metrics"]["mse"].as_f64().unwrap());
    assert!(t < f, "trimming the largest errors lowers the MSE: {t} vs {f}");
}

#[test]
fn scene_list_and_info_say_what_is_there() {
    let list = String::from_utf8(ok(&["scene", "list"]).stdout).unwrap();
    for (name, _) in wavetrace::scene::builtin::list() {
        assert!(list.lines().any(|l| l.starts_with(name)), "{name} listed:\n{list}");
    }
    assert!(list.contains("486 primitives"), "rtiow-final's size: {list}");
    if let Some(ctx) = common::gpu() {
        let info = String::from_utf8(ok(&["info"]).stdout).unwrap();
        for needle in ["adapters found", "chosen:", "subgroups:", "max storage binding:"] {
            assert!(info.contains(needle), "info lacks {needle}:\n{info}");
        }
        assert!(info.contains(&ctx.summary.name), "info names {}:\n{info}", ctx.summary.name);
    }
}
