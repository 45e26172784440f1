//! `wavetrace dispatch-cost` (issue 42): every variant's chain runs every dispatch in order (the
//! read-write chain's counter), each is timed on the GPU where the adapter has timestamps and on
//! the host, and bad sizes are refused with the flag's name.

use crate::common;
use wavetrace::measure::dispatch_cost::{measure, VARIANTS};

#[test]
fn every_variant_runs_its_whole_chain_and_is_timed() {
    let Some(ctx) = common::gpu() else { return };
    let report = measure(ctx, 12, 2).unwrap();
    assert_eq!(report.variants.len(), VARIANTS.len());
    assert_eq!(report.timestamps, ctx.summary.timestamps);
    for v in &report.variants {
        assert!(v.counter_ok, "{}: the counter lost a dispatch", v.variant.name);
        assert_eq!(v.compute_passes, if v.variant.one_pass { 1 } else { 12 }, "{}", v.variant.name);
        assert!(v.record_us_per_dispatch.median > 0.0 && v.round_trip_us_per_dispatch.median > 0.0);
        let s = v.round_trip_us_per_dispatch;
        assert!(s.min <= s.median && s.median <= s.max);
        match v.gpu_us_per_dispatch {
            Some(g) => assert!(g.median > 0.0 && g.min <= g.max, "{}: {g:?}", v.variant.name),
            None => assert!(!ctx.summary.timestamps, "{}: timestamps went missing", v.variant.name),
        }
    }
    // Today's recording (a pass per dispatch, direct, read-write) comes first, as the table says.
    let first = &report.variants[0].variant;
    assert!(!first.one_pass && !first.indirect && !first.read_only);
    assert!(report.table().lines().count() == 2 + VARIANTS.len());
}

#[test]
fn the_command_writes_json_and_refuses_bad_sizes() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::tmp().join("dispatch-cost");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("cost.json");
    let o = std::process::Command::new(common::bin())
        .args(["dispatch-cost", "--dispatches", "4", "--repetitions", "1", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["schema"], "wavetrace-dispatch-cost/1");
    assert_eq!(v["dispatches"], 4);
    assert!(v["adapter"]["name"].is_string() && v["build"]["git_commit"].is_string());
    assert_eq!(v["variants"].as_array().unwrap().len(), VARIANTS.len());
    assert!(String::from_utf8_lossy(&o.stdout).contains("pass-per-dispatch"));
    let o = std::process::Command::new(common::bin())
        .args(["dispatch-cost", "--dispatches", "0"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--dispatches must be in 1..="),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
