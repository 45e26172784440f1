//! The naive megakernel replayed: one lane per path sample in dispatch order (invocation i of a
//! dispatch takes pixel `pixel_offset + i % pixel_count`, sample `sample_start + i /
//! pixel_count`, as `shaders/megakernel.wgsl`), W consecutive invocations per subgroup, the
//! last subgroup of a dispatch partial; each subgroup runs the bounce loop in lockstep.

use super::lockstep::{slot, traverse, Lane, SlotCounts};
use super::paths::Paths;
use super::recorder::{is_hit, CLOSEST, SHADOW};
use super::width::MAX_WIDTH;
use super::ReplayJob;
use crate::cpu::camera::Camera;
use crate::gpu::dispatch_plan;
use crate::layout::DispatchParams;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use rayon::prelude::*;

/// What the replay simulates of the megakernel's launch.
#[derive(Clone, Copy, Debug)]
pub struct Launch {
    /// Most path samples per dispatch (`MegakernelOptions::samples_per_dispatch`).
    pub samples_per_dispatch: u64,
    /// Most threads per dispatch (workgroups per dimension × workgroup size).
    pub max_threads: u32,
    /// Replay one block of MAX_WIDTH invocations in `every` (1: the whole frame): systematic
    /// sampling of whole blocks, each replayed exactly, so a subgroup is never cut, the offset
    /// turning by one at each pass over the image's pixels.
    pub every: u64,
}

/// The replay of a frame at each width: slot counts, and the dispatches and blocks replayed.
pub struct Replayed {
    pub counts: Vec<(u32, SlotCounts)>,
    pub dispatches: usize,
    pub blocks: u64,
    pub blocks_replayed: u64,
}

/// Replays the naive megakernel at every width in `widths` (checked by `width::check`).
pub fn replay(job: ReplayJob, launch: Launch) -> Replayed {
    let ReplayJob { scene, frame, settings, widths } = job;
    let camera = Camera::<f32>::new(frame);
    let pixels = settings.width * settings.height;
    let plan = dispatch_plan::plan(pixels, settings.spp, launch.samples_per_dispatch, launch.max_threads);
    // (dispatch, first invocation) of every block; blocks never span dispatches.
    let blocks: Vec<(usize, u64)> = plan
        .iter()
        .enumerate()
        .flat_map(|(d, p)| {
            let n = p.pixel_count as u64 * p.sample_count as u64;
            (0..n.div_ceil(MAX_WIDTH as u64)).map(move |b| (d, b * MAX_WIDTH as u64))
        })
        .collect();
    let every = launch.every.max(1);
    let total = blocks.len() as u64;
    // One block in `every`, the offset turning by one at each pass over the image (the sample
    // number of the block's first invocation): where a pass holds a multiple of `every` blocks,
    // a fixed offset would draw the same pixels at every pass.
    let pass = |&(d, first): &(usize, u64)| plan[d].sample_start as u64 + first / plan[d].pixel_count as u64;
    let drawn = |i: usize| (i as u64 + pass(&blocks[i])).is_multiple_of(every);
    let replayed = (0..blocks.len()).filter(|&i| drawn(i)).count() as u64;
    let counts = blocks
        .par_iter()
        .enumerate()
        .filter(|(i, _)| drawn(*i))
        .map(|(_, &(d, first))| block(scene, &camera, settings, &plan[d], first, widths))
        .reduce(
            || widths.iter().map(|_| SlotCounts::new()).collect(),
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.add(b));
                a
            },
        );
    Replayed {
        counts: widths.iter().copied().zip(counts).collect(),
        dispatches: plan.len(),
        blocks: total,
        blocks_replayed: replayed,
    }
}

/// Records the paths of MAX_WIDTH invocations from `first` and replays them at every width.
fn block(
    scene: &PackedScene,
    camera: &Camera<f32>,
    settings: &RenderSettings,
    d: &DispatchParams,
    first: u64,
    widths: &[u32],
) -> Vec<SlotCounts> {
    let n = d.pixel_count as u64 * d.sample_count as u64;
    let paths = Paths::record(scene, camera, settings, d, first..(first + MAX_WIDTH as u64).min(n));
    widths
        .iter()
        .map(|&w| {
            let mut counts = SlotCounts::new();
            let mut lanes = paths.lanes();
            for group in lanes.chunks_mut(w as usize) {
                subgroup(group, w, &mut counts);
            }
            counts
        })
        .collect()
}

/// One subgroup's paths through the megakernel's bounce loop (shaders/shared/integrator.wgsl),
/// in lockstep: every instrumented block counted with the lanes that run it.
pub fn subgroup(lanes: &mut [Lane], width: u32, counts: &mut SlotCounts) {
    let mut alive: Vec<usize> = (0..lanes.len()).filter(|&l| lanes[l].next() == Some(CLOSEST)).collect();
    while !alive.is_empty() {
        alive = bounce(lanes, &alive, width, counts);
    }
}

/// One bounce (`trace_bounce`) of the lanes `alive`, each at its bounce's CLOSEST event, in
/// lockstep; returns the lanes whose path goes on (at their next CLOSEST).
pub fn bounce(lanes: &mut [Lane], alive: &[usize], width: u32, counts: &mut SlotCounts) -> Vec<usize> {
    let at = |lanes: &[Lane], l: usize, e: u32| lanes[l].next() == Some(e);
    counts.count(slot("megakernel_bounce"), alive.len(), width);
    alive.iter().for_each(|&l| lanes[l].at += 1);
    traverse(lanes, alive, slot("megakernel_traverse_inner"), width, counts);
    let hit: Vec<usize> = alive.iter().copied().filter(|&l| lanes[l].next().is_some_and(is_hit)).collect();
    counts.count(slot("megakernel_material"), hit.len(), width);
    let mut kinds = [0usize; 4];
    for &l in &hit {
        kinds[((lanes[l].next().unwrap() & 0xff) as usize).min(3)] += 1;
        lanes[l].at += 1;
    }
    for (k, name) in ["lambertian", "metal", "dielectric", "emissive"].iter().enumerate() {
        counts.count(slot(&format!("megakernel_{name}")), kinds[k], width);
    }
    let shadow: Vec<usize> = hit.iter().copied().filter(|&l| at(lanes, l, SHADOW)).collect();
    counts.count(slot("megakernel_shadow"), shadow.len(), width);
    shadow.iter().for_each(|&l| lanes[l].at += 1);
    traverse(lanes, &shadow, slot("megakernel_shadow_traverse_inner"), width, counts);
    hit.into_iter().filter(|&l| at(lanes, l, CLOSEST)).collect()
}
