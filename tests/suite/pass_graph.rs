//! The wavefront's pass graph is what runs: for a sample of legal knob sets the graph is
//! well formed and states each knob's passes and constants, and for a few of them rendered
//! the passes each label recorded are the graph's count.

use crate::common;
use wavetrace::gpu::label;
use wavetrace::gpu::timing::Timing;
use wavetrace::gpu::wavefront::graph::{Graph, Phase, Queue};
use wavetrace::gpu::wavefront::{self, Explained};
use wavetrace::method::{self, Method, MethodOptions};
use wavetrace::options::{
    self, Append, CompactStates, Compaction, ComputePasses, Launch, PoolSize, QueueOrder, RaySort, Refill,
    Scan, Schedule, ShadePasses, ShadowRays, Tail, WavefrontOptions,
};
use wavetrace::scene::builtin;
use wavetrace::settings::{Accel, RenderSettings};

fn settings() -> RenderSettings {
    RenderSettings {
        width: 8,
        height: 8,
        spp: 4,
        max_depth: 3,
        seed: 1,
        accel: Accel::Bvh,
        nee: true,
        roulette: false,
    }
}

/// A small counter-based generator: the same sample on every run.
struct Pick(u64);

impl Pick {
    fn of<T: Copy>(&mut self, v: &[T]) -> T {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        v[((self.0 >> 33) % v.len() as u64) as usize]
    }
}

/// `n` distinct knob sets that `options::check` accepts, drawn from every wavefront knob's values.
fn legal_knob_sets(n: usize) -> Vec<WavefrontOptions> {
    let mut p = Pick(0x5eed);
    let mut sets: Vec<WavefrontOptions> = Vec::new();
    for _ in 0..200_000 {
        if sets.len() == n {
            break;
        }
        let o = WavefrontOptions {
            pool_size: p.of(&[None, Some(PoolSize::Paths(64))]),
            workgroup_size: p.of(&[32, 64]),
            compaction: p.of(&[Compaction::Off, Compaction::Atomic, Compaction::Scan]),
            shade: p.of(&[
                ShadePasses::PerMaterial,
                ShadePasses::PerTexture,
                ShadePasses::Single,
                ShadePasses::Sorted,
            ]),
            schedule: p.of(&[Schedule::Waves, Schedule::Regenerate]),
            sync_every: p.of(&[8, 2]),
            batches_in_flight: p.of(&[3, 1]),
            tail: p.of(&[Tail::Off, Tail::Megakernel]),
            tail_threshold: p.of(&[0.05, 0.5]),
            chunk_pools: p.of(&[8, 2]),
            scan: p.of(&[Scan::Auto, Scan::Workgroup, Scan::Subgroup]),
            append: p.of(&[Append::Auto, Append::Lane, Append::Subgroup]),
            compute_passes: p.of(&[ComputePasses::Shared, ComputePasses::PerDispatch]),
            launch: p.of(&[Launch::Indirect, Launch::Pool]),
            shadow_rays: p.of(&[ShadowRays::Pass, ShadowRays::Inline]),
            queue_order: p.of(&[
                QueueOrder::Auto,
                QueueOrder::Arrival,
                QueueOrder::Slot,
                QueueOrder::SlotDepth,
            ]),
            refill_below: p.of(&[1.0, 0.5]),
            refill: p.of(&[Refill::Pass, Refill::InPlace]),
            compact_states: p.of(&[CompactStates::Off, CompactStates::On]),
            ray_sort: p.of(&[RaySort::Off, RaySort::Octant, RaySort::OctantCell]),
        };
        if options::check_wavefront(&o).is_ok() && !sets.contains(&o) {
            sets.push(o);
        }
    }
    assert_eq!(sets.len(), n, "the sampler found too few legal knob sets");
    sets
}

fn explain(o: &WavefrontOptions) -> Explained {
    let ctx = common::gpu().expect("checked by the caller");
    let scene = builtin::by_name("cornell").unwrap();
    let opts = MethodOptions { wavefront: *o, ..Default::default() };
    let (packed, _) = method::prepare(Method::Wavefront, &scene, &settings(), &opts).unwrap();
    wavefront::explain(ctx, &packed, &settings(), o, Timing::Passes).unwrap()
}

fn count(g: &Graph, l: &str) -> usize {
    g.passes.iter().filter(|p| p.label == l).count()
}

fn constant(g: &Graph, name: &str) -> f64 {
    g.constants.iter().find(|c| c.0 == name).unwrap_or_else(|| panic!("no {name}")).1
}

/// Each knob's passes and constants as the graph states them, and a graph a recorder can run:
/// every queue a pass consumes is produced, intersect fills the material queues before shade
/// reads them, and the timer's capacity covers the longest iteration.
#[test]
fn the_graph_states_every_knob_for_200_legal_knob_sets() {
    if common::gpu().is_none() {
        return;
    }
    for o in legal_knob_sets(200) {
        let e = explain(&o);
        let (g, r) = (&e.graph, &e.options);
        let what = format!("{o:?}");
        let regenerate = e.schedule == Schedule::Regenerate;
        assert_eq!(constant(g, "REGENERATE"), regenerate as u32 as f64, "{what}");
        assert_eq!(constant(g, "COMPACTION"), r.compaction as u32 as f64, "{what}");
        assert_eq!(constant(g, "SHADE_PASSES"), r.shade as u32 as f64, "{what}");
        assert_eq!(constant(g, "QUEUE_ORDER"), r.queue_order.word() as f64, "{what}");
        assert_eq!(constant(g, "LAUNCH_POOL"), (r.launch == Launch::Pool) as u32 as f64, "{what}");
        assert_eq!(count(g, label::REGENERATE), regenerate as usize, "{what}");
        assert_eq!(count(g, label::REGENERATE_INIT), regenerate as usize, "{what}");
        assert_eq!(count(g, label::GENERATE), !regenerate as usize, "{what}");
        assert_eq!(count(g, label::TAIL), (r.tail == Tail::Megakernel) as usize, "{what}");
        assert_eq!(count(g, label::RAY_SORT_COUNT), (r.ray_sort != RaySort::Off) as usize, "{what}");
        let compacts = (r.compact_states == CompactStates::On) as usize;
        assert_eq!(count(g, label::COMPACT_STATES_MOVE), compacts, "{what}");
        // cornell has lights: NEE's shadow pass unless its rays are traced inline.
        assert_eq!(count(g, label::SHADOW), (r.shadow_rays == ShadowRays::Pass) as usize, "{what}");
        assert_eq!(count(g, label::SHADE), (r.shade == ShadePasses::Single) as usize, "{what}");
        assert_eq!(count(g, label::SHADE_SORTED), (r.shade == ShadePasses::Sorted) as usize, "{what}");
        let sweep = r.queue_order == QueueOrder::Slot && r.compaction == Compaction::Atomic;
        assert_eq!(count(g, label::SLOT_SWEEP), sweep as usize, "{what}");
        let scans = (r.compaction == Compaction::Scan) as usize * 2
            + (r.compaction == Compaction::Atomic && r.queue_order == QueueOrder::SlotDepth) as usize;
        assert_eq!(count(g, label::COMPACT_SCATTER), scans, "{what}");
        let iteration: Vec<_> = g.phase(Phase::Iteration).collect();
        let at = |l: &str| iteration.iter().position(|p| p.label.starts_with(l));
        assert!(at("intersect") < at("shade"), "{what}");
        for p in &g.passes {
            for q in p.consumes.iter().filter(|q| !matches!(q, Queue::Slots)) {
                assert!(
                    g.passes.iter().any(|x| x.produces.contains(q)),
                    "{what}: nothing produces {q:?} for {}",
                    p.label
                );
            }
        }
        let decided = g.phase(Phase::Decided).count();
        for (refill, check) in [(false, false), (true, false), (false, true), (true, true)] {
            let n = g.iteration(refill, check).count() + if check { decided } else { 0 };
            assert!(n <= g.per_iteration(), "{what}");
        }
    }
}

/// Rendered, each label records as many passes as the graph says: waves, a start, each
/// iteration's passes per bounce and an end per wave; regenerating, the refills, the checks and
/// what they size as the schedule ran them.
#[test]
fn recorded_passes_are_the_graphs() {
    let Some(ctx) = common::gpu() else { return };
    let scene = builtin::by_name("cornell").unwrap();
    let s = settings();
    let small = |o: WavefrontOptions| WavefrontOptions { pool_size: Some(PoolSize::Paths(64)), ..o };
    let d = WavefrontOptions::default();
    let regen = WavefrontOptions { schedule: Schedule::Regenerate, sync_every: 2, ..d };
    for o in [
        small(d),
        small(WavefrontOptions { compaction: Compaction::Scan, shade: ShadePasses::Sorted, ..d }),
        small(WavefrontOptions { ray_sort: RaySort::Octant, queue_order: QueueOrder::Slot, ..d }),
        small(regen),
        small(WavefrontOptions {
            tail: Tail::Megakernel,
            compact_states: CompactStates::On,
            refill_below: 0.5,
            ..regen
        }),
        small(WavefrontOptions {
            refill: Refill::InPlace,
            shadow_rays: ShadowRays::Inline,
            queue_order: QueueOrder::SlotDepth,
            ..regen
        }),
    ] {
        let what = format!("{o:?}");
        let opts = MethodOptions { wavefront: o, ..Default::default() };
        let out = method::render(Method::Wavefront, &scene, &s, &opts, Some(ctx), &|_| {}).unwrap();
        let e = explain(&o);
        let (g, stats) = (&e.graph, out.schedule.as_ref().unwrap());
        let timings = out.timings.as_ref().unwrap();
        let shares = e.shares;
        let recorded = (stats.iterations + stats.speculative_iterations) as usize;
        // (Regenerating: batches of --sync-every iterations, checked at each batch's end or, with
        // the tail, after every one; the first refill starts every sample of a job no larger
        // than the pool.)
        let (waves, tail) = (e.schedule != Schedule::Regenerate, o.tail == Tail::Megakernel);
        let checks = if waves {
            0
        } else if tail {
            recorded
        } else {
            recorded / o.sync_every as usize
        };
        let paths = (s.width * s.height * s.spp) as usize;
        let refills = if paths <= e.pool as usize { shares } else { recorded };
        let mut expected = std::collections::BTreeMap::new();
        for p in &g.passes {
            let n = match p.phase {
                Phase::Start | Phase::End => shares,
                Phase::Decided => checks,
                Phase::Iteration if waves => s.max_depth as usize * shares,
                Phase::Iteration => match p.when {
                    wavetrace::gpu::wavefront::graph::When::Always => recorded,
                    wavetrace::gpu::wavefront::graph::When::Refill => refills,
                    wavetrace::gpu::wavefront::graph::When::Check => checks,
                    wavetrace::gpu::wavefront::graph::When::NoCheck => recorded - checks,
                },
            };
            *expected.entry(p.label).or_insert(0) += n as u64;
        }
        expected.retain(|_, n| *n > 0);
        let got: std::collections::BTreeMap<&str, u64> =
            timings.passes.iter().map(|(l, t)| (*l, t.passes)).collect();
        assert_eq!(got, expected, "{what}");
        assert_eq!(out.dispatches, expected.values().sum::<u64>() - stats.speculative_dispatches, "{what}");
    }
}

/// docs/methods.md shows `wavetrace plan`'s table for a job: its passes, phase by phase, are the
/// graph's for that job (the adapter's numbers aside: pool size, device limits).
#[test]
fn the_documented_plan_is_the_graphs() {
    let Some(ctx) = common::gpu() else { return };
    let doc = std::fs::read_to_string(common::root().join("docs/methods.md")).unwrap();
    let start = doc.find("$ wavetrace plan --scene cornell").expect("the plan's example in methods.md");
    let block = &doc[start..start + doc[start..].find("```").unwrap()];
    let documented: Vec<&str> = block
        .lines()
        .filter(|l| {
            l.starts_with("  ") && !l.trim_start().starts_with("pass ") && !l.trim_start().starts_with("--")
        })
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let scene = builtin::by_name("cornell").unwrap();
    let s = RenderSettings { width: 160, height: 90, spp: 16, max_depth: 50, ..settings() };
    let o = WavefrontOptions { schedule: Schedule::Regenerate, tail: Tail::Megakernel, ..Default::default() };
    let opts = MethodOptions { wavefront: o, ..Default::default() };
    let (packed, _) = method::prepare(Method::Wavefront, &scene, &s, &opts).unwrap();
    let e = wavefront::explain(ctx, &packed, &s, &o, Timing::Passes).unwrap();
    let labels: Vec<&str> = e.graph.passes.iter().map(|p| p.label).collect();
    assert_eq!(documented, labels, "regenerate docs/methods.md's block with the command it shows");
}
