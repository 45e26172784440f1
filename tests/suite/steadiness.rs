//! Timings that hold up (issue 47): GPU variants of a job take turns repetition by repetition
//! after a timed warm-up, every run records its warm-up, the runs it took turns with and how far
//! its repetitions spread, and a run whose repetitions spread beyond the threshold (or a GPU run
//! without warm-up) is flagged on every output.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use wavetrace::experiment::report::{ExperimentReport, RunRecord, RunStatus};

use crate::common;
use crate::experiment::{assert_valid, run_experiment, scratch, write_config};

fn config(methods: Value) -> Value {
    json!({
        "schema": "wavetrace-experiment/1",
        "question": "test",
        "scenes": ["three-spheres"],
        "resolutions": ["32x18"],
        "spp": [1],
        "max_depth": [8],
        "repetitions": 3,
        "methods": methods,
    })
}

fn run(name: &str, config: &Value) -> (ExperimentReport, std::path::PathBuf) {
    let dir = scratch(name);
    let path = write_config(&dir, name, config);
    let out = dir.join("out");
    let o = run_experiment(&path, &out, &dir.join("cache"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_valid(&out);
    (ExperimentReport::read(&out).unwrap(), out)
}

fn by_label<'a>(report: &'a ExperimentReport, label: &str) -> &'a RunRecord {
    report.runs.iter().find(|r| r.label == label).unwrap_or_else(|| panic!("no run {label}"))
}

#[test]
fn gpu_variants_take_turns_after_a_timed_warm_up() {
    if common::gpu().is_none() {
        return;
    }
    let mut c = config(json!([
        {"method": "cpu"},
        {"method": "megakernel"},
        {"method": "megakernel", "label": "mk-regenerate", "schedule": "regenerate"},
        {"method": "wavefront", "label": "waves", "schedule": "waves"}
    ]));
    // Any two frames agree (agree 10): the warm-up ends once the job has done 0.01 s of work
    // (frames of this job take from 20 µs to a few ms on llvmpipe).
    c["warmup"] = json!({"min_seconds": 0.01, "agree": 10, "max_frames": 1000});
    c["spp"] = json!([1, 2]);
    let (report, out) = run("steadiness-turns", &c);
    assert_eq!(report.runs.len(), 8);
    for r in &report.runs {
        assert_eq!(r.status, RunStatus::Ok, "{}: {:?}", r.id, r.error);
        let log = r.warmup_log.as_ref().expect("every run records its warm-up");
        assert_eq!(log.trace.len() as u32, log.frames);
        assert_eq!(r.warmup, log.frames);
        let st = r.stability.as_ref().expect("every run records its stability");
        let stat = r.timed_stat().unwrap();
        assert_eq!(stat.values.len(), 3);
        let spread = (stat.max - stat.min) / stat.median;
        assert!((st.spread.unwrap() - spread).abs() < 1e-12);
        assert_eq!(st.unstable, spread > 0.05, "{}: the flag follows the spread", r.id);
        assert!(!st.cold);
        assert!(st.median_low.unwrap() <= stat.median && stat.median <= st.median_high.unwrap());
        if r.method == "cpu" {
            assert_eq!(log.policy, "frames=1");
            assert!(r.interleaved_with.is_empty(), "CPU runs never take turns with GPU ones");
        } else {
            assert_eq!(log.policy, "timed");
            assert!(log.settled && log.frames >= 2, "{}: {log:?}", r.id);
            // The job's other GPU variants, and only those.
            let mut want: Vec<usize> = report
                .runs
                .iter()
                .filter(|o| o.method != "cpu" && o.spp == r.spp && o.index != r.index)
                .map(|o| o.index)
                .collect();
            want.sort();
            assert_eq!(r.interleaved_with, want, "{}", r.id);
        }
    }
    // The job's earlier runs' warm-up counts towards the later ones': the first warms up for
    // the job (0.05 s of its own work), the others count it in.
    let first = by_label(&report, "megakernel").warmup_log.clone().unwrap();
    let later = by_label(&report, "waves").warmup_log.clone().unwrap();
    assert_eq!(first.shared_seconds, 0.0);
    assert!(first.seconds >= 0.01);
    assert!(later.shared_seconds >= first.seconds);
    assert!(later.seconds + later.shared_seconds >= 0.01);
    // runs.csv carries the same.
    let (header, rows) = crate::tidy::assert_tidy(&out);
    let col =
        |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    for row in &rows {
        let r = &report.runs[row[col("index")].parse::<usize>().unwrap()];
        assert_eq!(row[col("unstable")], r.stability.as_ref().unwrap().unstable.to_string());
        assert_eq!(row[col("warmup_policy")], r.warmup_log.as_ref().unwrap().policy);
        let turns: Vec<String> = r.interleaved_with.iter().map(usize::to_string).collect();
        assert_eq!(row[col("interleaved_with")], turns.join(" "));
    }
}

#[test]
fn without_interleave_each_run_goes_alone_and_without_warm_up_it_is_cold() {
    if common::gpu().is_none() {
        return;
    }
    let mut c = config(json!([{"method": "megakernel"}, {"method": "wavefront", "schedule": "waves"}]));
    c["interleave"] = json!(false);
    c["warmup"] = json!(0);
    let (report, out) = run("steadiness-cold", &c);
    for r in &report.runs {
        assert!(r.interleaved_with.is_empty());
        assert_eq!(r.warmup, 0);
        assert_eq!(r.warmup_log.as_ref().unwrap().policy, "none");
        assert!(r.stability.as_ref().unwrap().cold && r.stability.as_ref().unwrap().flagged());
    }
    // Every page says so: the markdown page marks each time, the HTML shades the row.
    let md = wavetrace::experiment::markdown::page(
        &report,
        "out",
        &wavetrace::experiment::markdown::Links { charts: "", docs: None },
    );
    assert!(md.contains("none ⚠ cold") && md.contains("0 of 2 ok runs steady"), "{md}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("class=\"flagged\"") && html.contains("⚠ cold"));
}

/// A run whose repetitions a competing load disturbs is flagged; the same run left alone is
/// not. The competitor (sixteen threads on the two cores) is busy every other 300 ms while the
/// CPU reference renders nine repetitions of about 150 ms, so some repetitions run alone and
/// others get a ninth of the machine for part of their time: a spread of 100% and more. The
/// threshold is 50%, not the default 5%, and the undisturbed run gets five tries, the disturbed
/// one three. It runs alone (`scripts/test.sh` runs the ignored tests after the rest, one at a
/// time): beside the suite's other tests, which load the cores as they please, undisturbed
/// repetitions spread by up to 30%, and in one full run of four the disturbed run by less than
/// the bar.
#[test]
#[ignore = "timing-sensitive: scripts/test.sh runs it alone (cargo test -- --ignored --test-threads=1)"]
fn a_noisy_run_is_flagged_and_a_steady_one_is_not() {
    let mut c = config(json!([{"method": "cpu"}]));
    c["scenes"] = json!(["rtiow-final"]);
    c["resolutions"] = json!(["320x180"]);
    c["spp"] = json!([8]);
    c["repetitions"] = json!(9);
    c["unstable_spread"] = json!(0.5);
    let spread = |r: &ExperimentReport| r.runs[0].stability.clone().unwrap();

    // Where the load's busy phases fall among the repetitions is chance: a disturbed run gets
    // three tries (one failed in about one idle run of five, spreading 0.38–0.43 against the
    // 0.5 bar, since the CPU reference's repetitions grew from about 100 to about 150 ms).
    let mut disturbed = Vec::new();
    for _ in 0..3 {
        let stop = Arc::new(AtomicBool::new(false));
        let competitors: Vec<_> = (0..16)
            .map(|_| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let start = Instant::now();
                    let mut x = 0u64;
                    while !stop.load(Ordering::Relaxed) {
                        if (start.elapsed().as_millis() / 300).is_multiple_of(2) {
                            x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
                        } else {
                            std::thread::sleep(Duration::from_millis(5));
                        }
                    }
                    x
                })
            })
            .collect();
        let (noisy, _) = run("steadiness-noisy", &c);
        stop.store(true, Ordering::Relaxed);
        for t in competitors {
            std::hint::black_box(t.join().unwrap());
        }
        let s = spread(&noisy);
        if s.unstable && s.flagged() {
            break;
        }
        disturbed.push(s);
    }
    assert!(disturbed.len() < 3, "disturbed repetitions must be flagged: {disturbed:?}");

    let mut tries = Vec::new();
    for _ in 0..5 {
        let (steady, _) = run("steadiness-steady", &c);
        let s = spread(&steady);
        if !s.flagged() {
            return;
        }
        tries.push(s.spread);
    }
    panic!("left alone the run was flagged five times: spreads {tries:?}");
}
