//! The lockstep SIMD replay (issue 25): the CPU reference records what each path does, block by
//! block (traversal steps by kind, material, shadow traversal); the replay groups those paths
//! into subgroups of W lanes as a GPU method groups its threads and runs them in lockstep,
//! reconverging at the end of every loop and branch, counting the same slots as the device's
//! `--instrument` counters (`src/gpu/instrument.rs`). At W = the device's subgroup width it
//! reproduces the device's figures (tests/suite/simd_replay.rs); at other widths it predicts
//! them, with no GPU. Aila & Laine (2009) ran the same kind of simulator for traversal alone.
//!
//! Methods: the naive megakernel (one thread per sample, dispatch order), the regenerating
//! megakernel (persistent threads taking samples), the wavefront with `--schedule waves` (per
//! pass, queue order as the scan compaction leaves it) and with `--schedule regenerate` (the
//! refills, the schedule's checks, the sample ring's refill limit and the megakernel tail, as the
//! GPU's decision pass runs them). Large frames: a sampled subset per method (`--every`, see each module).

pub mod lockstep;
pub mod megakernel;
pub mod paths;
pub mod recorder;
pub mod regenerate;
pub mod wavefront;
pub mod width;

use crate::camera::CameraFrame;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;

/// What a replay runs: the scene, its camera, the job's settings, and the SIMD widths to count
/// at (checked by `width::check`).
#[derive(Clone, Copy)]
pub struct ReplayJob<'a> {
    pub scene: &'a PackedScene,
    pub frame: &'a CameraFrame,
    pub settings: &'a RenderSettings,
    pub widths: &'a [u32],
}

impl<'a> ReplayJob<'a> {
    pub fn new(
        scene: &'a PackedScene,
        frame: &'a CameraFrame,
        settings: &'a RenderSettings,
        widths: &'a [u32],
    ) -> Self {
        Self { scene, frame, settings, widths }
    }
}
