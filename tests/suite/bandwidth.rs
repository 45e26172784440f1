//! `wavetrace bandwidth` (issue 44): each way moves the bytes it says and is timed on the GPU where
//! the adapter has timestamps; both copies copy; bad sizes are refused with the flag's name.

use crate::common;
use wavetrace::measure::bandwidth::{measure, WAYS};

#[test]
fn every_way_is_timed_and_both_copies_copy() {
    let Some(ctx) = common::gpu() else { return };
    let report = measure(ctx, 2, 2).unwrap();
    assert!(report.copy_ok, "a copy lost or changed elements");
    assert_eq!(report.buffer_bytes, 2 << 20);
    assert_eq!(report.ways.iter().map(|w| w.way).collect::<Vec<_>>(), WAYS);
    for w in &report.ways {
        // The read moves the buffer once; the copies read it and write the destination.
        let moved = if w.way == "stream_read" { 2 << 20 } else { 4 << 20 };
        assert_eq!(w.bytes, moved, "{}", w.way);
        let r = w.round_trip_gb_per_s;
        assert!(r.min > 0.0 && r.min <= r.median && r.median <= r.max, "{}: {r:?}", w.way);
        match w.gpu_gb_per_s {
            // The GPU's time is within the round trip's, so its rate is at least the round trip's.
            Some(g) => assert!(g.median >= r.median, "{}: {g:?} against {r:?}", w.way),
            None => assert!(!ctx.summary.timestamps, "{}: timestamps went missing", w.way),
        }
    }
    assert_eq!(report.table().lines().count(), 3 + WAYS.len());
}

#[test]
fn the_command_writes_json_and_refuses_bad_sizes() {
    let Some(ctx) = common::gpu() else { return };
    let dir = common::tmp().join("bandwidth");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("bandwidth.json");
    let o = std::process::Command::new(common::bin())
        .args(["bandwidth", "--mib", "1", "--repetitions", "1", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["schema"], "wavetrace-bandwidth/1");
    assert_eq!(v["buffer_bytes"], 1 << 20);
    assert_eq!(v["copy_ok"], true);
    assert!(v["adapter"]["name"].is_string() && v["build"]["git_commit"].is_string());
    let largest = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size) >> 20;
    for bad in ["0".to_string(), (largest + 1).to_string()] {
        let o =
            std::process::Command::new(common::bin()).args(["bandwidth", "--mib", &bad]).output().unwrap();
        assert!(!o.status.success(), "--mib {bad} was accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--mib must be in 1..="), "{err}");
    }
}
