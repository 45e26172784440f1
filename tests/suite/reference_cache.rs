//! The reference cache and user references (issue 29): shards running at once render a missing
//! reference once (a lock on the entry, src/experiment/cache_lock.rs), a stale lock does not
//! block, a damaged cached entry is detected and replaced, and a user-supplied EXR reference is
//! used as given. Tiny CPU renders through the binary.

use crate::experiment::{scratch, small_config, wavetrace, write_config};

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::SystemTime;

use wavetrace::experiment::cache_lock::{self, Claim, STALE_AFTER};
use wavetrace::experiment::report::ExperimentReport;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// One CPU run (16x9, 2 spp) against a 4-spp CPU reference.
fn one_run_config(dir: &Path) -> PathBuf {
    let mut config = small_config(serde_json::json!([{"method": "cpu"}]));
    config["resolutions"] = serde_json::json!(["16x9"]);
    config["spp"] = serde_json::json!([2]);
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"] = serde_json::json!({"method": "cpu", "spp": 4});
    write_config(dir, "one-run", &config)
}

fn run(config: &Path, out: &Path, cache: &Path) -> String {
    let o = wavetrace(&["experiment", "run", s(config), "--out", s(out), "--cache", s(cache)]);
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "experiment run failed:\n{stderr}");
    stderr
}

/// The cache entry's file name, learnt from a run into a cache of its own.
fn entry_name(dir: &Path, config: &Path) -> String {
    run(config, &dir.join("probe"), &dir.join("probe-cache"));
    let report = ExperimentReport::read(&dir.join("probe")).unwrap();
    format!("{}.exr", report.references[0].key)
}

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Two shards asking for the same missing reference at once render it once: while a live lock
/// is held (here by this test process) both wait, saying so; when it goes, one claims and
/// renders, the other reads what it wrote. Without the lock both render at once and neither says
/// it waits (the check below fails rather than hangs: a shard that finishes without waiting ends
/// its stream).
#[test]
fn shards_at_once_render_a_missing_reference_once() {
    let dir = scratch("ref-lock-concurrent");
    let config = one_run_config(&dir);
    let entry = entry_name(&dir, &config);
    let cache = dir.join("cache");
    std::fs::create_dir_all(&cache).unwrap();
    let lock = cache_lock::lock_path(&cache.join(&entry));
    std::fs::write(&lock, cache_lock::lock_text(std::process::id(), &cache_lock::host_name())).unwrap();

    let (tx, rx) = mpsc::channel();
    let mut children = Vec::new();
    let mut readers = Vec::new();
    for i in 0..2 {
        let out = dir.join(format!("shard{i}"));
        let mut child = Command::new(crate::common::bin())
            .args(["experiment", "run", s(&config), "--out", s(&out), "--cache", s(&cache)])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = child.stderr.take().unwrap();
        let tx = tx.clone();
        readers.push(std::thread::spawn(move || {
            let mut text = String::new();
            let mut told = false;
            for line in BufReader::new(stderr).lines() {
                let line = line.unwrap();
                if !told && line.contains("waiting for") {
                    tx.send((i, true)).unwrap();
                    told = true;
                }
                text += &line;
                text.push('\n');
            }
            if !told {
                tx.send((i, false)).unwrap();
            }
            text
        }));
        children.push((child, out));
    }
    for _ in 0..2 {
        let (i, waited) = rx.recv().unwrap();
        assert!(waited, "shard {i} finished without waiting for the held lock");
    }
    std::fs::remove_file(&lock).unwrap();

    let mut rendered = 0;
    let mut from_cache = 0;
    let mut stderr_all = String::new();
    for ((mut child, out), reader) in children.into_iter().zip(readers) {
        let status = child.wait().unwrap();
        let text = reader.join().unwrap();
        assert!(status.success(), "{text}");
        assert!(text.contains(&format!("waiting for {}", lock.display())), "{text}");
        let report = ExperimentReport::read(&out).unwrap();
        if report.references[0].cached {
            from_cache += 1;
        } else {
            rendered += 1;
        }
        stderr_all += &text;
    }
    assert_eq!((rendered, from_cache), (1, 1), "one shard renders, one reads:\n{stderr_all}");
    assert_eq!(stderr_all.matches("rendering reference").count(), 1, "{stderr_all}");
    // The entry and nothing else: no lock, no temporary file left behind.
    assert_eq!(files(&cache), [entry]);
}

/// A lock whose holder died does not block: a process of this host that has exited is seen at
/// once; a holder elsewhere whose heartbeat stopped over `STALE_AFTER` ago is taken over, a fresh
/// one is waited for. A lock a run takes is removed when it is done.
#[test]
fn a_stale_reference_lock_is_taken_over() {
    let dir = scratch("ref-lock-stale");
    let config = one_run_config(&dir);
    let entry = entry_name(&dir, &config);
    let cache = dir.join("cache");
    std::fs::create_dir_all(&cache).unwrap();
    let lock = cache_lock::lock_path(&cache.join(&entry));

    // A shard on this host that was killed while rendering: its pid is gone.
    let mut gone = Command::new("true").spawn().unwrap();
    let dead_pid = gone.id();
    gone.wait().unwrap();
    std::fs::write(&lock, cache_lock::lock_text(dead_pid, &cache_lock::host_name())).unwrap();
    let stderr = run(&config, &dir.join("out"), &cache);
    assert!(stderr.contains("taking over the stale reference lock"), "{stderr}");
    assert!(stderr.contains(&format!("process {dead_pid} on this host has exited")), "{stderr}");
    assert!(!stderr.contains("waiting for"), "{stderr}");
    assert!(!ExperimentReport::read(&dir.join("out")).unwrap().references[0].cached);
    assert_eq!(files(&cache), [entry]);

    // A holder on another host: waited for while its heartbeat is fresh, taken over once stale.
    let other = dir.join("other.exr.lock");
    std::fs::write(&other, cache_lock::lock_text(1, "elsewhere.invalid")).unwrap();
    match cache_lock::try_claim(&other, STALE_AFTER).unwrap() {
        Claim::Held(h) => assert_eq!((h.pid, h.host.as_str()), (Some(1), "elsewhere.invalid")),
        Claim::Mine(_) => panic!("a fresh lock of another host was taken"),
    }
    let file = std::fs::File::options().write(true).open(&other).unwrap();
    file.set_modified(SystemTime::now() - 2 * STALE_AFTER).unwrap();
    drop(file);
    match cache_lock::try_claim(&other, STALE_AFTER).unwrap() {
        Claim::Mine(held) => {
            let me = cache_lock::read_holder(&other).unwrap().unwrap();
            assert_eq!(me.pid, Some(std::process::id()), "the lock now names this process");
            drop(held);
            assert!(!other.exists(), "a dropped lock is removed");
        }
        Claim::Held(h) => panic!("a lock {h} was not taken over"),
    }
    // A live holder on this host (this very process) is waited for.
    std::fs::write(&other, cache_lock::lock_text(std::process::id(), &cache_lock::host_name())).unwrap();
    assert!(matches!(cache_lock::try_claim(&other, STALE_AFTER).unwrap(), Claim::Held(_)));
}

/// A damaged cached reference (truncated, as a full disk or a killed copy leaves it) is detected,
/// said so, rendered again and replaced by the same image; the next run reads it from the cache.
#[test]
fn a_damaged_cached_reference_is_detected_and_replaced() {
    let dir = scratch("ref-damaged");
    let config = one_run_config(&dir);
    let cache = dir.join("cache");
    run(&config, &dir.join("first"), &cache);
    let first = ExperimentReport::read(&dir.join("first")).unwrap();
    let entry = cache.join(format!("{}.exr", first.references[0].key));
    let (good, _) = wavetrace::image_io::read_exr(&entry).unwrap();
    let bytes = std::fs::read(&entry).unwrap();
    std::fs::write(&entry, &bytes[..bytes.len() / 2]).unwrap();

    let stderr = run(&config, &dir.join("second"), &cache);
    assert!(stderr.contains("is unreadable") && stderr.contains("rendering it again"), "{stderr}");
    let second = ExperimentReport::read(&dir.join("second")).unwrap();
    assert!(!second.references[0].cached, "the damaged entry was used");
    let (replaced, _) = wavetrace::image_io::read_exr(&entry).unwrap();
    assert_eq!(replaced.data, good.data, "the replacement is the same reference");
    let relmse = |r: &ExperimentReport| r.runs[0].error_metrics.as_ref().unwrap().relmse;
    assert_eq!(relmse(&second), relmse(&first));

    let stderr = run(&config, &dir.join("third"), &cache);
    assert!(!stderr.contains("rendering reference"), "{stderr}");
    assert!(ExperimentReport::read(&dir.join("third")).unwrap().references[0].cached);
}

/// A user-supplied EXR reference (`"reference": {"exr": pattern}`, relative to the config) is used
/// as given: a run that renders exactly that image (same method, spp and seed) has zero error, a
/// run at more samples does not, and the record takes what the file's attributes say. The
/// reference is written by `wavetrace render`, as a user would make one.
#[test]
fn a_user_exr_reference_is_used_as_given() {
    let dir = scratch("ref-user-exr");
    std::fs::create_dir_all(dir.join("refs")).unwrap();
    let exr = dir.join("refs/three-spheres-16x9.exr");
    let o = wavetrace(&[
        "render",
        "--scene",
        "three-spheres",
        "--method",
        "cpu",
        "--width",
        "16",
        "--height",
        "9",
        "--spp",
        "2",
        "--max-depth",
        "8",
        "--out",
        s(&exr),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut config = small_config(serde_json::json!([{"method": "cpu"}]));
    config["resolutions"] = serde_json::json!(["16x9"]);
    config["spp"] = serde_json::json!([2, 8]);
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"] = serde_json::json!({"exr": "refs/{scene}-{width}x{height}.exr"});
    let config = write_config(&dir, "user-ref", &config);
    let cache = dir.join("cache");
    let stderr = run(&config, &dir.join("out"), &cache);
    assert!(!stderr.contains("rendering reference"), "{stderr}");
    assert!(!cache.exists() || files(&cache).is_empty(), "a user reference is not cached");

    let report = ExperimentReport::read(&dir.join("out")).unwrap();
    assert_eq!(report.references.len(), 1);
    let r = &report.references[0];
    assert_eq!(r.kind, "exr");
    assert!(Path::new(&r.exr).ends_with("refs/three-spheres-16x9.exr"), "{}", r.exr);
    assert_eq!((r.method.as_deref(), r.spp, r.max_depth, r.seed), (Some("cpu"), Some(2), Some(8), Some(0)));
    let relmse: Vec<(u32, f64)> =
        report.runs.iter().map(|r| (r.spp, r.error_metrics.as_ref().unwrap().relmse)).collect();
    assert_eq!(relmse.len(), 2, "{relmse:?}");
    for (spp, e) in relmse {
        if spp == 2 {
            assert_eq!(e, 0.0, "the run that rendered the reference's own image");
        } else {
            assert!(e > 0.0, "spp {spp}: relMSE {e}");
        }
    }
}
