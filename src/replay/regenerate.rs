//! The regenerating megakernel replayed (`shaders/megakernel_regenerate.wgsl` with
//! `megakernel/take_sample_subgroup.wgsl`): persistent threads in subgroups of W lanes loop one
//! bounce per iteration; at the top of every iteration the lanes whose path ended take the next
//! samples of the dispatch, consecutive ones in lane order (one atomic per subgroup), until the
//! dispatch runs out or a lane has started `paths_per_thread` paths in this launch; the subgroup
//! leaves the loop when every lane is out of work (`leave_together`).
//!
//! Which subgroup takes which samples depends on how the device interleaves subgroups, which
//! the atomic leaves undetermined. The replay runs `resident` subgroups at a time, one loop
//! iteration each in turn, a finished one replaced by the next of the launch: all of them for
//! a GPU that holds every thread at once, the driver's worker threads for llvmpipe, which runs
//! a workgroup's subgroups one after the other, each to its end (no barriers to switch at).

use super::lockstep::{extrapolate, Lane, SlotCounts};
use super::megakernel::bounce;
use super::paths::Paths;
use super::wavefront::regenerating_subset;
use super::ReplayJob;
use crate::cpu::camera::Camera;
use crate::gpu::dispatch_plan;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};
use rayon::prelude::*;
use std::collections::VecDeque;

/// What the replay simulates of the regenerating megakernel's launch.
#[derive(Clone, Copy, Debug)]
pub struct Launch {
    /// Most path samples per dispatch (`MegakernelOptions::samples_per_dispatch`).
    pub samples_per_dispatch: u64,
    /// Persistent threads (`--threads`, rounded up to whole workgroups).
    pub threads: u32,
    pub workgroup_size: u32,
    /// Most paths a thread starts per launch (llvmpipe's loop cap; None: no limit).
    pub paths_per_thread: Option<u32>,
    /// Subgroups that run at once (None: every subgroup of the launch).
    pub resident: Option<u32>,
    /// The sampled subset: 1 replays the whole frame; k > 1 two prefixes of ⌈spp / k⌉ and twice
    /// as many samples of every pixel, each as a job of its own, extrapolated to the frame
    /// (`wavefront::regenerating_subset`, the threads standing for the pool).
    pub every: u64,
}

impl Launch {
    /// The persistent threads launched: `threads` rounded up to whole workgroups.
    fn launched_threads(&self) -> u32 {
        self.threads.div_ceil(self.workgroup_size) * self.workgroup_size
    }
}

/// The replay at each width: slot counts and trace dispatches (launches).
pub struct Replayed {
    pub counts: Vec<(u32, SlotCounts)>,
    pub dispatches: usize,
    /// Samples replayed (all of the frame's without a subset).
    pub samples_replayed: u64,
}

/// Replays the regenerating megakernel at every width in `widths`.
pub fn replay(job: ReplayJob, launch: Launch) -> Result<Replayed> {
    let settings = job.settings;
    if launch.threads == 0 || launch.workgroup_size == 0 || launch.resident == Some(0) {
        bail!("replay of the regenerating megakernel: threads, workgroup size and resident subgroups must be at least 1");
    }
    if launch.every == 0 {
        bail!("--every must be at least 1 (1: the whole frame)");
    }
    let threads = launch.launched_threads();
    // The threads a launch of the whole frame runs: the subset's prefixes must hold several
    // such sets of samples.
    let job_threads =
        (threads as u64).min((settings.sample_count()).next_multiple_of(launch.workgroup_size as u64));
    let short = regenerating_subset(settings, launch.every, job_threads, "--every")?;
    if short.spp == settings.spp {
        return replay_job(job, launch);
    }
    let long = RenderSettings { spp: 2 * short.spp, ..settings.clone() };
    let a = replay_job(ReplayJob { settings: &short, ..job }, launch)?;
    let b = replay_job(ReplayJob { settings: &long, ..job }, launch)?;
    let f = (settings.sample_count() - short.sample_count()) as f64
        / (long.sample_count() - short.sample_count()) as f64;
    Ok(Replayed {
        counts: a
            .counts
            .iter()
            .zip(&b.counts)
            .map(|((w, x), (_, y))| (*w, SlotCounts::extrapolate(x, y, f)))
            .collect(),
        dispatches: extrapolate(a.dispatches as u64, b.dispatches as u64, f) as usize,
        samples_replayed: a.samples_replayed + b.samples_replayed,
    })
}

/// [`replay`] of the whole of `settings`' frame.
fn replay_job(job: ReplayJob, launch: Launch) -> Result<Replayed> {
    let ReplayJob { scene, frame, settings, widths } = job;
    let camera = Camera::<f32>::new(frame);
    let threads = launch.launched_threads();
    let per_thread = launch.paths_per_thread.map_or(u64::MAX, |p| p.max(1) as u64);
    // As src/gpu/megakernel.rs: a dispatch holds no more samples than its threads can take.
    let budget = launch.samples_per_dispatch.min((threads as u64).saturating_mul(per_thread));
    let plan = dispatch_plan::plan(settings.width * settings.height, settings.spp, budget, u32::MAX);
    let mut counts: Vec<SlotCounts> = widths.iter().map(|_| SlotCounts::new()).collect();
    let mut dispatches = 0;
    let mut samples_replayed = 0;
    for d in &plan {
        let n = d.pixel_count as u64 * d.sample_count as u64;
        samples_replayed += n;
        let paths = Paths::record(scene, &camera, settings, d, 0..n);
        let launched = threads.min((n as u32).next_multiple_of(launch.workgroup_size));
        let launches = n.div_ceil(launched as u64 * per_thread.min(n));
        dispatches += launches as usize;
        let per_width: Vec<SlotCounts> = widths
            .par_iter()
            .map(|&w| {
                let mut c = SlotCounts::new();
                let mut lanes = paths.lanes();
                let mut next = 0usize;
                for _ in 0..launches {
                    run_launch(&mut lanes, &mut next, launched, per_thread, w, launch.resident, &mut c);
                }
                debug_assert_eq!(next, lanes.len(), "every sample taken");
                c
            })
            .collect();
        counts.iter_mut().zip(&per_width).for_each(|(a, b)| a.add(b));
    }
    Ok(Replayed { counts: widths.iter().copied().zip(counts).collect(), dispatches, samples_replayed })
}

/// A persistent subgroup's lanes: the sample each traces (None: none live), paths taken this
/// launch, whether it is out of work.
struct Subgroup {
    live: Vec<Option<usize>>,
    taken: Vec<u64>,
    out: Vec<bool>,
}

/// One launch of `threads` persistent threads; `next` is the dispatch's sample counter.
fn run_launch(
    lanes: &mut [Lane],
    next: &mut usize,
    threads: u32,
    per_thread: u64,
    width: u32,
    resident: Option<u32>,
    counts: &mut SlotCounts,
) {
    let w = width as usize;
    // Subgroups of the launch, the last partial when the launch is not a multiple of W.
    let mut waiting: VecDeque<usize> =
        (0..threads as usize).step_by(w).map(|first| w.min(threads as usize - first)).collect();
    let room = resident.map_or(usize::MAX, |r| r as usize);
    let mut running: Vec<Subgroup> = Vec::new();
    loop {
        while running.len() < room {
            let Some(size) = waiting.pop_front() else { break };
            running.push(Subgroup { live: vec![None; size], taken: vec![0; size], out: vec![false; size] });
        }
        if running.is_empty() {
            return;
        }
        // One loop iteration of each running subgroup, in turn.
        running.retain_mut(|s| iteration(s, lanes, next, per_thread, width, counts));
    }
}

/// One iteration of a subgroup's loop; false when it leaves the loop.
fn iteration(
    s: &mut Subgroup,
    lanes: &mut [Lane],
    next: &mut usize,
    per_thread: u64,
    width: u32,
    counts: &mut SlotCounts,
) -> bool {
    if s.out.iter().all(|&o| o) {
        return false;
    }
    for l in 0..s.live.len() {
        if s.live[l].is_some() || s.out[l] {
            continue;
        }
        // NO_SAMPLE past the thread's share, or past the dispatch: out of work.
        if s.taken[l] >= per_thread || *next >= lanes.len() {
            s.out[l] = true;
            continue;
        }
        s.live[l] = Some(*next);
        s.taken[l] += 1;
        *next += 1;
    }
    let alive: Vec<usize> = s.live.iter().flatten().copied().collect();
    if !alive.is_empty() {
        let going = bounce(lanes, &alive, width, counts);
        for l in s.live.iter_mut() {
            if l.is_some_and(|i| !going.contains(&i)) {
                *l = None;
            }
        }
    }
    true
}
