//! Batched refills and state compaction (issue 26, `--refill-below`, `--compact-states`): they
//! change which slots a sample takes and when it starts, never what it computes, so every
//! combination gives the waves' film bit for bit; bad values are refused naming the knob; and
//! compaction does what it is for, measured by the coherence counters.

use crate::common;
use crate::common::render_wavefront as run;

use wavetrace::gpu::wavefront::{
    CompactStates, Compaction, QueueOrder, Schedule, ScheduleStats, Tail, WavefrontOptions,
};
use wavetrace::options::PoolSize;
use wavetrace::settings::{Accel, RenderSettings};

fn settings(width: u32, height: u32, spp: u32, nee: bool) -> RenderSettings {
    RenderSettings { width, height, spp, max_depth: 12, seed: 5, accel: Accel::Bvh, nee, roulette: false }
}

fn regenerating(pool: u32) -> WavefrontOptions {
    WavefrontOptions {
        pool_size: Some(PoolSize::Paths(pool)),
        schedule: Schedule::Regenerate,
        ..Default::default()
    }
}

/// Both compaction methods, arrival and slot orders, with and without NEE (the shadow weight
/// moves with its path), the tail and a ring of two chunks (refills stop at its end), a pool
/// refilled about five times: the same film as waves, bit for bit (with the tail: the same paths,
/// radiance up to rounding, `common::assert_same_paths`), each case on one of the scenes. With
/// compaction every refill compacts (and something moves), and a lower threshold refills less
/// often.
#[test]
fn batched_refills_and_state_compaction_give_the_waves_film() {
    let Some(_) = common::gpu() else { return };
    for (i, (scene, nee)) in [("cornell", true), ("rtiow-final", false)].into_iter().enumerate() {
        let s = settings(40, 24, 8, nee);
        let waves = run(
            scene,
            &s,
            WavefrontOptions { pool_size: Some(PoolSize::Paths(1500)), ..Default::default() },
            false,
        )
        .unwrap()
        .film;
        assert!(waves.image_mean() > 0.0, "{scene}: a black film proves nothing");
        let cases = [
            (Compaction::Atomic, QueueOrder::Arrival, Tail::Off, 8),
            (Compaction::Atomic, QueueOrder::Slot, Tail::Megakernel, 8),
            (Compaction::Atomic, QueueOrder::Arrival, Tail::Megakernel, 2),
            (Compaction::Scan, QueueOrder::Arrival, Tail::Off, 2),
            (Compaction::Scan, QueueOrder::SlotDepth, Tail::Off, 8),
        ];
        // The cases take the scenes in turn (each run compiles its own pipelines: most of this
        // test's cost with a cold shader cache).
        for (compaction, queue_order, tail, chunk_pools) in cases.into_iter().skip(i).step_by(2) {
            let mut refills = Vec::new();
            for (below, compact) in [
                (1.0, CompactStates::On),
                (0.5, CompactStates::Off),
                (0.5, CompactStates::On),
                (0.2, CompactStates::On),
            ] {
                let wf = WavefrontOptions {
                    compaction,
                    queue_order,
                    tail,
                    chunk_pools,
                    refill_below: below,
                    compact_states: compact,
                    ..regenerating(1500)
                };
                let what = format!(
                    "{scene} nee={nee} {compaction:?} {queue_order:?} {tail:?} chunk_pools={chunk_pools} \
                     refill_below={below} {compact:?}"
                );
                let out = run(scene, &s, wf, false).unwrap();
                common::assert_waves_film(&what, &out.film, &waves, tail);
                let st: ScheduleStats = out.schedule.unwrap();
                assert_eq!(
                    (st.refill_below, st.compact_states),
                    (Some(below), Some(compact == CompactStates::On))
                );
                if compact == CompactStates::On {
                    assert!(st.compactions >= 5 && st.states_moved > 0, "{what}: {st:?}");
                    refills.push(st.compactions);
                } else {
                    assert_eq!((st.compactions, st.states_moved), (0, 0), "{what}");
                }
            }
            // Compactions count the refills: where the ring does not cut refills short (it does
            // with two chunks, whose end moves as chunks complete), a lower threshold refills less
            // often (5 pools of samples: every refill but the first waits for the threshold).
            if chunk_pools == 8 && tail == Tail::Off {
                assert!(
                    refills[0] > refills[1] && refills[1] > refills[2],
                    "{scene} {compaction:?}: {refills:?}"
                );
            }
        }
    }
}

/// Bad values and combinations are refused before anything runs, naming the knob and why.
#[test]
fn refill_knobs_are_checked() {
    let Some(_) = common::gpu() else { return };
    let s = settings(8, 8, 1, false);
    for (wf, says) in [
        (
            WavefrontOptions { refill_below: 0.0, ..regenerating(64) },
            "--refill-below must be a live fraction",
        ),
        (WavefrontOptions { refill_below: 1.5, ..regenerating(64) }, "in (0, 1], got 1.5"),
        (
            WavefrontOptions { refill_below: 0.5, schedule: Schedule::Waves, ..Default::default() },
            "needs --schedule regenerate",
        ),
        (
            WavefrontOptions {
                compact_states: CompactStates::On,
                schedule: Schedule::Waves,
                ..Default::default()
            },
            "--compact-states on compacts the pool before refills: it needs --schedule regenerate",
        ),
        (
            WavefrontOptions {
                compact_states: CompactStates::On,
                compaction: Compaction::Off,
                ..regenerating(64)
            },
            "it needs --compaction on",
        ),
    ] {
        let err = run("three-spheres", &s, wf, false).unwrap_err().to_string();
        assert!(err.contains(says), "{err}");
    }
}

/// What state compaction is for: with batched refills in arrival order, a refill's samples take
/// whatever slots paths left, scattered over the pool; compacted first, they take one contiguous
/// run of slots in sample order, so an intersect subgroup's lanes read fewer lines of path state
/// (the coherence counters' `lines`, over the whole render).
#[test]
fn state_compaction_puts_a_refill_in_one_run_of_slots() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.summary.subgroups {
        common::skipped(
            "refill::state_compaction_puts_a_refill_in_one_run_of_slots",
            "the coherence counters need subgroup operations",
        );
        return;
    }
    let s = settings(64, 48, 16, false);
    for compaction in [Compaction::Atomic, Compaction::Scan] {
        let lines = |compact_states| {
            let wf = WavefrontOptions {
                compaction,
                queue_order: QueueOrder::Arrival,
                refill_below: 0.5,
                compact_states,
                ..regenerating(4096)
            };
            let c = run("rtiow-final", &s, wf, true).unwrap().coherence.unwrap();
            let subgroups: u64 = c.iter().map(|b| b.subgroups).sum();
            assert!(subgroups > 1000, "{compact_states:?}: {subgroups} subgroups");
            c.iter().map(|b| b.lines * b.subgroups as f64).sum::<f64>() / subgroups as f64
        };
        let (off, on) = (lines(CompactStates::Off), lines(CompactStates::On));
        eprintln!("{compaction:?}: lines per intersect subgroup: compact-states off {off:.2}, on {on:.2}");
        assert!(on < 0.9 * off, "{compaction:?}: compacted {on:.2} lines vs {off:.2}");
    }
}
