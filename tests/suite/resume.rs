//! `experiment run --resume`: after a real SIGKILL mid-sweep (a shard of it), the finished runs
//! are kept as they were (records byte for byte, images untouched) and only the rest rendered;
//! a changed config, another shard or an unprovable build is refused, naming what differs;
//! failed runs are run again; `--resume` without a report starts afresh.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant, SystemTime};

use serde_json::Value;

use crate::experiment::{assert_valid, read_if_any, scratch, small_config, wavetrace, write_config};
use crate::tidy::assert_tidy;

/// `wavetrace experiment run CONFIG --out OUT --cache CACHE EXTRA...`.
fn run(config: &Path, out: &Path, cache: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["experiment", "run", config.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend(["--cache", cache.to_str().unwrap()]);
    args.extend(extra);
    wavetrace(&args)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Modification times of a run's image files.
fn image_times(out: &Path, run: &Value) -> Vec<SystemTime> {
    ["exr", "png", "error_map"]
        .iter()
        .map(|k| std::fs::metadata(out.join(run["images"][k].as_str().unwrap())).unwrap().modified().unwrap())
        .collect()
}

/// Copies a report directory (report.json and images) for a test that edits it.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to.join("images")).unwrap();
    std::fs::copy(from.join("report.json"), to.join("report.json")).unwrap();
    for e in std::fs::read_dir(from.join("images")).unwrap().flatten() {
        std::fs::copy(e.path(), to.join("images").join(e.file_name())).unwrap();
    }
}

#[test]
fn a_killed_shard_resumes_without_rendering_its_finished_runs_again() {
    let dir = scratch("resume-killed");
    let config = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres", "rtiow-final"],
        "resolutions": ["128x72"],
        "spp": [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12],
        "repetitions": 3,
        "warmup": 0,
        "methods": [{"method": "cpu"}, {"method": "cpu-f64"}],
        "reference": {"method": "cpu-f64", "spp": 16}
    });
    let path = write_config(&dir, "sweep", &config);
    let (out, cache) = (dir.join("out"), dir.join("cache"));

    // Kill the shard (SIGKILL) once at least two runs are recorded.
    let mut child = Command::new(crate::common::bin())
        .args(["experiment", "run", path.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .args(["--cache", cache.to_str().unwrap(), "--shard", "1/2"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while read_if_any(&out).is_none_or(|r| r["runs"].as_array().unwrap().len() < 2) {
        assert!(start.elapsed() < Duration::from_secs(120), "the experiment made no progress");
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = assert_valid(&out);
    let selected = before["runs_selected"].as_u64().unwrap() as usize;
    let kept: Vec<Value> = before["runs"].as_array().unwrap().clone();
    assert_eq!(before["status"], "running");
    assert!(kept.len() >= 2 && kept.len() < selected, "killed after {} of {selected} runs", kept.len());
    let times: Vec<Vec<SystemTime>> = kept.iter().map(|r| image_times(&out, r)).collect();
    let untouched = std::fs::read(out.join("report.json")).unwrap();

    // Refusals name what differs and leave the directory as it was.
    let mut changed = config.clone();
    changed["repetitions"] = 2.into();
    let changed = write_config(&dir, "changed", &changed);
    let o = run(&changed, &out, &cache, &["--resume", "--shard", "1/2"]);
    assert!(!o.status.success() && stderr(&o).contains("the config differs"), "{}", stderr(&o));
    assert!(stderr(&o).contains("changed: repetitions"), "{}", stderr(&o));
    let o = run(&path, &out, &cache, &["--resume", "--shard", "0/2"]);
    assert!(!o.status.success(), "another shard");
    assert!(stderr(&o).contains("run with --shard 1/2, this is --shard 0/2"), "{}", stderr(&o));
    let o = run(&path, &out, &cache, &["--resume"]);
    assert!(!o.status.success() && stderr(&o).contains("this is no --shard"), "{}", stderr(&o));
    assert_eq!(std::fs::read(out.join("report.json")).unwrap(), untouched, "a refusal writes nothing");

    // Another build: refused unless --allow-other-build, which the report then records.
    let other = dir.join("other-build");
    copy_dir(&out, &other);
    let mut r = before.clone();
    r["environments"][0]["build"]["git_commit"] = "0123abc-dirty".into();
    r["environments"][0]["build"]["executable_digest"] = "fnv1a64:0000000000000000".into();
    std::fs::write(other.join("report.json"), serde_json::to_string_pretty(&r).unwrap()).unwrap();
    let o = run(&path, &other, &cache, &["--resume", "--shard", "1/2"]);
    let e = stderr(&o);
    assert!(!o.status.success() && e.contains("another build") && e.contains("0123abc-dirty"), "{e}");
    assert!(e.contains("--allow-other-build"), "{e}");
    let o = run(&path, &other, &cache, &["--resume", "--allow-other-build", "--shard", "1/2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = assert_valid(&other);
    assert_eq!(r["environments"][1]["resume"]["other_build"], true);
    assert_eq!(r["environments"][0]["build"]["git_commit"], "0123abc-dirty", "each run's build stays named");

    // The resume proper.
    let o = run(&path, &out, &cache, &["--resume", "--shard", "1/2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains(&format!("keeping {} finished runs", kept.len())), "{}", stderr(&o));
    let after = assert_valid(&out);
    assert_eq!(after["status"], "complete");
    let runs = after["runs"].as_array().unwrap();
    let indices: Vec<u64> = runs.iter().map(|r| r["index"].as_u64().unwrap()).collect();
    let expected: Vec<u64> = (0..after["runs_planned"].as_u64().unwrap()).filter(|i| i % 2 == 1).collect();
    assert_eq!(indices, expected, "every run of the shard once, in plan order");
    let envs = after["environments"].as_array().unwrap();
    assert_eq!(envs.len(), 2, "the killed process and the resuming one");
    assert!(envs[0]["finished"].is_null() && envs[1]["finished"].is_string());
    assert!(envs.iter().all(|e| e["shard"] == serde_json::json!({"index": 1, "count": 2})));
    let kept_indices: Vec<&Value> = kept.iter().map(|r| &r["index"]).collect();
    assert_eq!(envs[1]["resume"]["kept"].as_array().unwrap().iter().collect::<Vec<_>>(), kept_indices);
    assert_eq!(envs[1]["resume"]["retried"], serde_json::json!([]));
    for (old, t) in kept.iter().zip(&times) {
        let new = runs.iter().find(|r| r["index"] == old["index"]).unwrap();
        let mut expected = old.clone();
        expected["resumed"] = true.into();
        assert_eq!(new, &expected, "a kept run's record is as it was");
        assert_eq!(&image_times(&out, new), t, "{}: a kept run's images are not written again", old["id"]);
    }
    for r in runs.iter().filter(|r| !kept_indices.contains(&&r["index"])) {
        assert_eq!(
            (r["resumed"].as_bool(), r["environment"].as_u64()),
            (Some(false), Some(1)),
            "{}",
            r["id"]
        );
        assert_eq!(r["status"], "ok");
        assert!(out.join(r["images"]["exr"].as_str().unwrap()).is_file());
    }
    let (header, rows) = assert_tidy(&out);
    let resumed = header.iter().position(|h| h == "resumed").unwrap();
    assert_eq!(rows.iter().filter(|r| r[resumed] == "true").count(), kept.len());
    assert!(out.join("report.html").is_file());

    // Resuming a complete shard renders nothing.
    let o = run(&path, &out, &cache, &["--resume", "--shard", "1/2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("keeping {} finished runs, running 0", runs.len())),
        "{}",
        stderr(&o)
    );
    let again = assert_valid(&out);
    for (a, b) in runs.iter().zip(again["runs"].as_array().unwrap()) {
        assert_eq!(a["wall_seconds"], b["wall_seconds"], "{}", a["id"]);
    }
}

#[test]
fn resume_runs_failed_runs_again_and_starts_afresh_without_a_report() {
    let dir = scratch("resume-failed");
    let mut config = small_config(serde_json::json!([{"method": "cpu"}, {"method": "megakernel"}]));
    // No adapter has this name, so every GPU run fails, on any machine.
    config["adapter"] = Value::String("no-such-adapter-anywhere".into());
    let path = write_config(&dir, "failing", &config);
    let (out, cache): (PathBuf, PathBuf) = (dir.join("out"), dir.join("cache"));

    // A requeued job passes --resume from its first start on: no report yet is a fresh start.
    let o = run(&path, &out, &cache, &["--resume"]);
    assert!(!o.status.success(), "failed runs make the exit status fail");
    assert!(stderr(&o).contains("nothing to resume, starting afresh"), "{}", stderr(&o));
    let first = assert_valid(&out);
    assert_eq!(first["status"], "complete");
    assert_eq!(first["environments"].as_array().unwrap().len(), 1);
    assert!(first["environments"][0]["resume"].is_null());

    // Failed runs are run again; the runs that succeeded are kept.
    let o = run(&path, &out, &cache, &["--resume"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("keeping 2 finished runs, running 2 (2 failed before, run again)"),
        "{}",
        stderr(&o)
    );
    let second = assert_valid(&out);
    let resume = &second["environments"][1]["resume"];
    let retried = resume["retried"].as_array().unwrap();
    assert_eq!(retried.len(), 2);
    assert!(retried.iter().all(|r| r["error"].as_str().unwrap().contains("no-such-adapter-anywhere")));
    for r in second["runs"].as_array().unwrap() {
        let again = r["method"] == "megakernel";
        assert_eq!(r["resumed"], !again, "{}", r["id"]);
        assert_eq!(r["environment"], if again { 1 } else { 0 }, "{}", r["id"]);
        assert_eq!(r["status"], if again { "failed" } else { "ok" }, "{}", r["id"]);
        let listed = if again { retried } else { resume["kept"].as_array().unwrap() };
        assert!(listed.iter().any(|x| x == &r["index"] || x["index"] == r["index"]), "{}", r["id"]);
    }
    assert_tidy(&out);

    // Without --resume the report is replaced, as before, and the note says --resume exists.
    let o = run(&path, &out, &cache, &[]);
    let e = stderr(&o);
    assert!(e.contains("holds a complete report of failing") && e.contains("--resume"), "{e}");
    assert_eq!(assert_valid(&out)["environments"].as_array().unwrap().len(), 1);
}
