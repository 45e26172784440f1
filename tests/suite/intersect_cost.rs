//! `wavetrace intersect-cost` (issue 44, item 1b): the diagnostic intersect that makes its camera
//! rays in place traces the rays the wavefront's intersect traces (the same hits, whatever the
//! pool and the workgroup size, and the same tally every repetition), and both are timed.

use crate::common;
use wavetrace::measure::intersect_cost::{measure, IntersectCost, IntersectCostReport};
use wavetrace::scene::Scene;
use wavetrace::settings::{Accel, RenderSettings};

fn job(scene: &str, workgroup_size: u32, pool_size: Option<u32>) -> IntersectCostReport {
    let ctx = common::gpu().unwrap();
    let settings = RenderSettings {
        width: 40,
        height: 24,
        spp: 2,
        max_depth: 1,
        seed: 7,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    };
    let job = IntersectCost { settings, workgroup_size, pool_size, repetitions: 2, preheat_seconds: 0.0 };
    measure(ctx, &Scene::resolve(scene).unwrap(), &job).unwrap()
}

#[test]
fn the_registers_pass_hits_what_intersect_hits() {
    let Some(ctx) = common::gpu() else { return };
    // A pool of 500 paths: intersect runs in four waves, the registers pass in one dispatch.
    let final_scene = job("rtiow-final", 64, Some(500));
    assert_eq!(final_scene.rays, 40 * 24 * 2);
    assert_eq!(final_scene.pool, 500);
    assert_eq!(final_scene.intersect.hits, final_scene.registers.hits);
    // The book's sky shows above the spheres: some rays miss, most hit.
    let hits = final_scene.registers.hits;
    assert!(hits > final_scene.rays / 2 && hits < final_scene.rays, "{hits} of {}", final_scene.rays);
    for pass in [&final_scene.intersect, &final_scene.registers] {
        match pass.ns_per_ray {
            Some(ns) => {
                assert!(ns.median > 0.0 && ns.min <= ns.median && ns.median <= ns.max, "{}", pass.pass)
            }
            None => assert!(!ctx.summary.timestamps, "{}: timestamps went missing", pass.pass),
        }
    }
    assert_eq!(final_scene.registers_over_intersect.is_some(), ctx.summary.timestamps);
    // Other lanes and waves, the same rays: the same hits on the same primitives.
    let regrouped = job("rtiow-final", 32, None);
    assert_eq!(
        (regrouped.registers.hits, regrouped.checksum),
        (final_scene.registers.hits, final_scene.checksum)
    );
    // Another scene (quads, an emitter) hits other primitives.
    let cornell = job("cornell", 64, Some(500));
    assert_eq!(cornell.intersect.hits, cornell.registers.hits);
    assert_ne!(cornell.checksum, final_scene.checksum);
    // Title, header, a row per pass and, with timestamps, their ratio.
    assert_eq!(final_scene.table().lines().count(), 4 + ctx.summary.timestamps as usize);
}

#[test]
fn the_command_writes_json_and_refuses_no_repetitions() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::tmp().join("intersect-cost");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("cost.json");
    let size = ["--scene", "three-spheres", "--width", "16", "--height", "8", "--spp", "2"];
    let o = std::process::Command::new(common::bin())
        .arg("intersect-cost")
        .args(size)
        .args(["--repetitions", "1", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["schema"], "wavetrace-intersect-cost/1");
    assert_eq!(v["rays"], 16 * 8 * 2);
    assert_eq!(v["intersect"]["hits"], v["registers"]["hits"]);
    assert_eq!(v["registers"]["pass"], "intersect_registers");
    assert!(v["adapter"]["name"].is_string() && v["build"]["git_commit"].is_string());
    assert!(String::from_utf8_lossy(&o.stdout).contains("intersect_registers"));
    let o = std::process::Command::new(common::bin())
        .arg("intersect-cost")
        .args(size)
        .args(["--repetitions", "0"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--repetitions must be at least 1"), "{err}");
}
