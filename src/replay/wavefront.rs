//! The wavefront replayed per pass (src/gpu/wavefront/). `--schedule waves`: per wave, generate
//! over the wave's paths, then per bounce intersect over the ray queue, one shade pass per
//! material kind the scene uses (or one over every hit), and with NEE the shadow pass. Each pass
//! runs one thread per queue entry, W consecutive entries per subgroup, the last subgroup of
//! every dispatch partial, and counts the slots `--instrument` counts.
//!
//! Queue order is arrival order (`--queue-order arrival`) or slot order (`slot`, `slot-depth`;
//! see [`Wave::regenerate`]). Arrival order is the one `--compaction-method scan` leaves, which
//! is stable over the producing pass's positions: intersect's positions in order → each
//! material queue; shade's positions (material queues laid end to end in kind order) → the next
//! ray queue and, in the same order, the shadow queue (appended atomically on the device, see
//! below). `--compaction-method atomic` leaves whatever order the atomics run in, which no
//! replay can know: it is modelled by the scan's order, which atomics aggregated per subgroup
//! approach when subgroups append in dispatch order. With
//! `--compaction off` every pass runs over the whole wave, one thread per path, and the lanes
//! whose path is not in that pass's queue idle. `--schedule regenerate`: see
//! [`Wave::regenerate`] (no megakernel tail; the sample ring's refill limit is not modelled).

use super::lockstep::{slot, traverse, Lane, SlotCounts};
use super::paths::Paths;
use super::recorder::{is_hit, is_step, CLOSEST, SHADOW};
use crate::camera::CameraFrame;
use crate::cpu::camera::Camera;
use crate::gpu::schedule::Schedule;
use crate::gpu::wavefront::schedule::{shares, CHUNK_POOLS};
use crate::gpu::wavefront::{Compaction, QueueOrder, ShadePasses};
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// What the replay simulates of the wavefront's launch.
#[derive(Clone, Copy, Debug)]
pub struct Launch {
    /// Paths in flight (`--pool-size`; the device's default is 2^20, at most the samples).
    pub pool: u32,
    pub compaction: Compaction,
    pub shade: ShadePasses,
    /// `waves`, or `regenerate`: refills into the free slots every iteration.
    pub schedule: Schedule,
    /// The order of the queues (`auto` resolved as the device resolves it).
    pub queue_order: QueueOrder,
}

/// The replay at each width: slot counts; per pass, dispatches recorded and how many were
/// empty (zero workgroups: nothing queued).
pub struct Replayed {
    pub counts: Vec<(u32, SlotCounts)>,
    pub dispatches: BTreeMap<String, Dispatches>,
    pub waves: usize,
    /// The queue order replayed (`auto` resolved).
    pub queue_order: QueueOrder,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Dispatches {
    pub recorded: u64,
    pub empty: u64,
}

/// Replays the wavefront (waves) at every width in `widths`.
pub fn replay(
    scene: &PackedScene,
    frame: &CameraFrame,
    settings: &RenderSettings,
    widths: &[u32],
    launch: Launch,
) -> Result<Replayed> {
    if launch.pool == 0 {
        bail!("replay of the wavefront: the pool must hold at least 1 path");
    }
    let regenerate = launch.schedule == Schedule::Regenerate;
    if regenerate && launch.compaction == Compaction::Off {
        bail!(
            "replay of the regenerating wavefront: --compaction off runs passes over the pool by slot, which \
             follows the free list's atomic order; replay it with --compaction on"
        );
    }
    let camera = Camera::<f32>::new(frame);
    let pool = launch.pool.min(u32::try_from(settings.sample_count()).unwrap_or(u32::MAX));
    launch.queue_order.check(launch.compaction)?;
    let order = launch.queue_order.resolve(launch.schedule, launch.compaction, settings.sample_count(), pool);
    let plan =
        shares(launch.schedule, settings.width * settings.height, settings.spp, pool, settings.max_depth);
    // The sample ring's refill limit binds only when a share holds more samples than the ring
    // (CHUNK_POOLS pools); the host moves it at its checks, which the replay does not model.
    let ring = CHUNK_POOLS as u64 * pool as u64;
    let share = |d: &crate::layout::DispatchParams| d.pixel_count as u64 * d.sample_count as u64;
    if let Some(d) = plan.iter().find(|d| regenerate && share(d) > ring) {
        bail!(
            "replay of the regenerating wavefront: a share of {} samples is more than its sample ring holds \
             ({CHUNK_POOLS} pools of {pool}), whose refill limit the replay does not model; use a --pool-size \
             of at least {}",
            share(d),
            share(d).div_ceil(CHUNK_POOLS as u64)
        );
    }
    let kinds = scene.material_kinds_used();
    let shadow_pass = settings.nee && !scene.lights.is_empty();
    let mut counts: Vec<SlotCounts> = widths.iter().map(|_| SlotCounts::new()).collect();
    let mut dispatches = BTreeMap::new();
    for d in &plan {
        let n = d.pixel_count as u64 * d.sample_count as u64;
        let paths = Paths::record(scene, &camera, settings, d, 0..n);
        let per_width: Vec<(SlotCounts, BTreeMap<String, Dispatches>)> = widths
            .par_iter()
            .map(|&w| {
                let lanes = paths.lanes();
                let n = lanes.len();
                let mut wave = Wave {
                    lanes,
                    width: w,
                    counts: SlotCounts::new(),
                    dispatches: BTreeMap::new(),
                    compaction: launch.compaction != Compaction::Off,
                    // In waves, slot l traces sample l.
                    slot_of: if order.is_slot() { (0..n).collect() } else { Vec::new() },
                    first_bounce: vec![false; if order == QueueOrder::SlotDepth { n } else { 0 }],
                };
                if regenerate {
                    wave.regenerate(pool as usize, &kinds, launch.shade, shadow_pass);
                } else {
                    wave.waves(settings.max_depth, &kinds, launch.shade, shadow_pass);
                }
                (wave.counts, wave.dispatches)
            })
            .collect();
        for (a, (b, _)) in counts.iter_mut().zip(&per_width) {
            a.add(b);
        }
        for (pass, n) in &per_width[0].1 {
            let e: &mut Dispatches = dispatches.entry(pass.clone()).or_default();
            e.recorded += n.recorded;
            e.empty += n.empty;
        }
    }
    Ok(Replayed {
        counts: widths.iter().copied().zip(counts).collect(),
        dispatches,
        waves: plan.len(),
        queue_order: order,
    })
}

/// One wave's paths at one width.
struct Wave<'a> {
    lanes: Vec<Lane<'a>>,
    width: u32,
    counts: SlotCounts,
    dispatches: BTreeMap<String, Dispatches>,
    /// Whether passes run over queues (scan or atomic) rather than the whole wave.
    compaction: bool,
    /// Slot order: each lane's slot in the pool (empty in arrival order).
    slot_of: Vec<usize>,
    /// Keyed by depth: whether the lane's path was started by the last refill (its next ray is
    /// its first bounce); empty without the key.
    first_bounce: Vec<bool>,
}

impl Wave<'_> {
    /// `--schedule waves`: every path starts together; `max_depth` iterations.
    fn waves(&mut self, max_depth: u32, kinds: &[u32], shade: ShadePasses, shadow_pass: bool) {
        let all: Vec<usize> = (0..self.lanes.len()).collect();
        let threads: Vec<Option<usize>> = all.iter().map(|&l| Some(l)).collect();
        self.pass("generate", &threads, |_, _| {});
        let mut rays = all;
        for _ in 0..max_depth {
            rays = self.iteration(&rays, kinds, shade, shadow_pass);
        }
    }

    /// `--schedule regenerate`: before every iteration the refill starts the next samples in
    /// the slots free (the pool less the paths still queued), appended at the ray queue's end
    /// in sample order; iterations go on until every path has ended. In arrival order which slot
    /// a refill takes (the free list is a stack) does not move a lane in a compacted queue. In
    /// slot order it does: the refill takes the lowest free slots in ascending order (the scan's
    /// free list), and the next ray queue and the shadow queue list their paths by slot; keyed
    /// by depth, the last refill's paths (about to trace their first bounce) after the others.
    fn regenerate(&mut self, pool: usize, kinds: &[u32], shade: ShadePasses, shadow_pass: bool) {
        let n = self.lanes.len();
        let slot_order = !self.slot_of.is_empty();
        let mut free: std::collections::BTreeSet<usize> =
            if slot_order { (0..pool).collect() } else { Default::default() };
        let (mut next, mut rays) = (0, Vec::new());
        // Slot order: which lanes are still queued after an iteration (reset after each use).
        let mut live = vec![false; if slot_order { n } else { 0 }];
        loop {
            let refill: Vec<usize> = (next..n.min(next + pool - rays.len())).collect();
            next += refill.len();
            if !self.first_bounce.is_empty() {
                rays.iter().for_each(|&l: &usize| self.first_bounce[l] = false);
                refill.iter().for_each(|&l| self.first_bounce[l] = true);
            }
            if slot_order {
                for &l in &refill {
                    self.slot_of[l] = free.pop_first().expect("a free slot for every refill");
                }
            }
            if !refill.is_empty() {
                let threads: Vec<Option<usize>> = refill.iter().map(|&l| Some(l)).collect();
                self.pass("generate", &threads, |_, _| {});
                rays.extend(refill);
            }
            if rays.is_empty() {
                return;
            }
            let before = rays;
            rays = self.iteration(&before, kinds, shade, shadow_pass);
            if slot_order {
                // The slots of the paths that ended are free for the next refill.
                rays.iter().for_each(|&l| live[l] = true);
                free.extend(before.iter().filter(|&&l| !live[l]).map(|&l| self.slot_of[l]));
                rays.iter().for_each(|&l| live[l] = false);
            }
        }
    }

    /// In slot order, `queue` as the scan over the pool lists it: by slot; keyed by depth
    /// (`first_key`), the paths on their first bounce after the others.
    fn slot_sort(&self, queue: &mut [usize], first_key: bool) {
        if self.slot_of.is_empty() {
            return;
        }
        let key = |l: usize| (first_key && self.first_bounce.get(l) == Some(&true), self.slot_of[l]);
        queue.sort_by_key(|&l| key(l));
    }

    /// One iteration over the ray queue `rays`: intersect, shade pass by pass, shadow; returns
    /// the next ray queue.
    fn iteration(
        &mut self,
        rays: &[usize],
        kinds: &[u32],
        shade: ShadePasses,
        shadow_pass: bool,
    ) -> Vec<usize> {
        let names = ["lambertian", "metal", "dielectric", "emissive"];
        // Intersect: closest hits; hits go to their material's queue in queue order.
        let mut material: [Vec<usize>; 4] = Default::default();
        let queue = self.queue(rays);
        self.pass("intersect", &queue, |wave, active| {
            active.iter().for_each(|&l| wave.lanes[l].at += 1);
            traverse(&mut wave.lanes, active, slot("intersect_traverse_inner"), wave.width, &mut wave.counts);
        });
        for &l in rays {
            if let Some(e) = self.lanes[l].next().filter(|&e| is_hit(e)) {
                let k = if shade == ShadePasses::PerMaterial { (e & 0xff).min(3) as usize } else { 0 };
                material[k].push(l);
            }
        }
        // Shade, pass by pass in kind order: the next ray queue and the shadow queue.
        let (mut next, mut shadow) = (Vec::new(), Vec::new());
        let passes: Vec<(usize, String)> = match shade {
            ShadePasses::PerMaterial => {
                kinds.iter().map(|&k| (k as usize, format!("shade_{}", names[(k as usize).min(3)]))).collect()
            }
            ShadePasses::Single => vec![(0, "shade".to_string())],
        };
        for (k, name) in passes {
            let queue = self.queue(&material[k]);
            self.pass(&name, &queue, |_, _| {});
            for &l in &material[k] {
                let lane = &mut self.lanes[l];
                lane.at += 1;
                if lane.next() == Some(SHADOW) {
                    shadow.push(l);
                }
                if after_shadow(lane) == Some(CLOSEST) {
                    next.push(l);
                }
            }
        }
        self.slot_sort(&mut shadow, false);
        self.slot_sort(&mut next, true);
        if shadow_pass {
            let queue = self.queue(&shadow);
            self.pass("shadow", &queue, |wave, active| {
                active.iter().for_each(|&l| wave.lanes[l].at += 1);
                traverse(
                    &mut wave.lanes,
                    active,
                    slot("shadow_traverse_inner"),
                    wave.width,
                    &mut wave.counts,
                );
            });
        }
        next
    }

    /// A pass's threads: the queue's entries in order, or without compaction the whole wave
    /// with the paths not in `queued` idle (None).
    fn queue(&self, queued: &[usize]) -> Vec<Option<usize>> {
        if self.compaction {
            return queued.iter().map(|&l| Some(l)).collect();
        }
        let mut threads = vec![None; self.lanes.len()];
        queued.iter().for_each(|&l| threads[l] = Some(l));
        threads
    }

    /// One dispatch of pass `name` over `threads`, W per subgroup: the entry slot counted with
    /// each subgroup's active lanes, then `body` run on them in lockstep.
    fn pass(&mut self, name: &str, threads: &[Option<usize>], mut body: impl FnMut(&mut Self, &[usize])) {
        let d = self.dispatches.entry(name.to_string()).or_default();
        d.recorded += 1;
        d.empty += threads.is_empty() as u64;
        for group in threads.chunks(self.width as usize) {
            let active: Vec<usize> = group.iter().flatten().copied().collect();
            self.counts.count(slot(name), active.len(), self.width);
            if !active.is_empty() {
                body(self, &active);
            }
        }
    }
}

/// The lane's next event past a pending shadow ray's traversal (what follows the bounce).
fn after_shadow(lane: &Lane) -> Option<u32> {
    let mut i = lane.at;
    if lane.events.get(i) == Some(&SHADOW) {
        i += 1;
        while lane.events.get(i).is_some_and(|&e| is_step(e)) {
            i += 1;
        }
    }
    lane.events.get(i).copied()
}
