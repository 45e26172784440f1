//! The ray sort (issue 26, `--ray-sort`): it changes only the order in which intersect's lanes
//! take the queued rays, never what a path computes, so every schedule gives the waves' film bit
//! for bit; it does what it is for (a subgroup's rays leave in fewer directions, measured by the
//! coherence counters); it is refused where there is no queue to sort.

use crate::common;
use crate::common::render_wavefront as run;

use wavetrace::gpu::wavefront::{Compaction, QueueOrder, RaySort, Schedule, Tail, WavefrontOptions};
use wavetrace::options::Named;
use wavetrace::options::PoolSize;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(width: u32, height: u32, spp: u32, nee: bool) -> RenderSettings {
    RenderSettings { width, height, spp, max_depth: 12, seed: 7, accel: Accel::Bvh, nee, roulette: false }
}

/// Waves and regenerate (with the tail, arrival and slot order), both compaction methods, with
/// and without NEE: the same film as the unsorted waves, bit for bit, for both keys (with the
/// tail: the same paths, radiance up to rounding, `common::assert_same_paths`), each case and
/// key on one of the scenes.
#[test]
fn sorted_rays_give_the_waves_film() {
    let Some(_) = common::gpu() else { return };
    for (i, (scene, nee)) in [("cornell", true), ("rtiow-final", false)].into_iter().enumerate() {
        let s = settings(40, 24, 8, nee);
        let base = WavefrontOptions { pool_size: Some(PoolSize::Paths(1500)), ..Default::default() };
        let waves = run(scene, &s, base, false).unwrap().film;
        assert!(waves.image_mean() > 0.0, "{scene}: a black film proves nothing");
        let regenerate = WavefrontOptions { schedule: Schedule::Regenerate, ..base };
        let cases = [
            (Compaction::Atomic, base),
            (Compaction::Scan, base),
            (Compaction::Atomic, WavefrontOptions { queue_order: QueueOrder::Arrival, ..regenerate }),
            (
                Compaction::Scan,
                WavefrontOptions { queue_order: QueueOrder::Slot, tail: Tail::Megakernel, ..regenerate },
            ),
            (
                Compaction::Atomic,
                WavefrontOptions { queue_order: QueueOrder::Arrival, tail: Tail::Megakernel, ..regenerate },
            ),
        ];
        // Each (case, key) pair on one scene, in turn: both keys meet NEE (each run compiles its
        // own pipelines: most of this test's cost with a cold shader cache).
        for (c, (compaction, wf)) in cases.into_iter().enumerate() {
            for (k, ray_sort) in [RaySort::Octant, RaySort::OctantCell].into_iter().enumerate() {
                if (c + k + i) % 2 != 0 {
                    continue;
                }
                let wf = WavefrontOptions { compaction, ray_sort, ..wf };
                let out = run(scene, &s, wf, false).unwrap();
                let what = format!(
                    "{scene} nee={nee} {compaction:?} {:?} {:?} {:?} {ray_sort:?}",
                    wf.schedule, wf.queue_order, wf.tail
                );
                common::assert_waves_film(&what, &out.film, &waves, wf.tail);
                assert_eq!(out.schedule.unwrap().ray_sort, Some(ray_sort.name()), "{what}");
            }
        }
    }
}

/// What the sort is for: after a few bounces a queue's neighbouring rays leave in unrelated
/// directions (a diffuse bounce picks any of the hemisphere's octants); sorted by octant, a
/// subgroup's rays share one but where a key's run ends. The coherence counters' distinct
/// octants per intersect subgroup, over the whole render, must fall below half, and the cell key
/// keeps that (its runs are shorter, so allow a little more).
#[test]
fn sorting_puts_a_subgroup_s_rays_in_one_octant() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        common::skipped(
            "ray_sort::sorting_puts_a_subgroup_s_rays_in_one_octant",
            "the coherence counters need subgroup operations",
        );
        return;
    }
    let s = settings(64, 48, 16, false);
    for compaction in [Compaction::Atomic, Compaction::Scan] {
        let octants = |ray_sort| {
            let wf = WavefrontOptions {
                compaction,
                ray_sort,
                pool_size: Some(PoolSize::Paths(4096)),
                schedule: Schedule::Regenerate,
                ..Default::default()
            };
            let c = run("rtiow-final", &s, wf, true).unwrap().coherence.unwrap();
            let subgroups: u64 = c.iter().map(|b| b.subgroups).sum();
            assert!(subgroups > 1000, "{ray_sort:?}: {subgroups} subgroups");
            c.iter().map(|b| b.octants * b.subgroups as f64).sum::<f64>() / subgroups as f64
        };
        let (off, octant, cell) =
            (octants(RaySort::Off), octants(RaySort::Octant), octants(RaySort::OctantCell));
        eprintln!(
            "{compaction:?}: octants per intersect subgroup: unsorted {off:.2}, octant {octant:.2}, octant-cell {cell:.2}"
        );
        assert!(off > 2.0, "{compaction:?}: unsorted rays should mix octants: {off:.2}");
        assert!(octant < 0.5 * off, "{compaction:?}: sorted by octant {octant:.2} vs {off:.2}");
        assert!(cell < 0.6 * off, "{compaction:?}: sorted by octant and cell {cell:.2} vs {off:.2}");
    }
}

/// No queue, no sort: refused before anything runs, naming the knob.
#[test]
fn a_sort_without_queues_is_refused() {
    let Some(_) = common::gpu() else { return };
    let wf =
        WavefrontOptions { ray_sort: RaySort::Octant, compaction: Compaction::Off, ..Default::default() };
    let err = run("three-spheres", &settings(8, 8, 1, false), wf, false).unwrap_err().to_string();
    assert!(
        err.contains("--ray-sort octant sorts the ray queue") && err.contains("--compaction on"),
        "{err}"
    );
}
