//! What every GPU method returns: the film and how the render went.

use super::instrument::SimdEfficiency;
use super::memory::GpuMemory;
use super::timing::Timings;
use crate::film::Film;
use std::collections::BTreeMap;

/// A GPU render's film and how it went.
#[derive(Clone, Debug)]
pub struct GpuRender {
    pub film: Film,
    pub timings: Timings,
    /// Dispatches recorded, empty ones included.
    pub dispatches: u64,
    /// Compute passes they were recorded in (`dispatches` unless the wavefront's dispatches
    /// share passes: `--compute-passes shared`).
    pub compute_passes: u64,
    /// Of those, indirect dispatches the GPU sized to zero workgroups (wavefront).
    pub empty_dispatches: Option<u64>,
    pub wall_seconds: f64,
    /// SIMD efficiency per instrumented point (`--instrument` only).
    pub simd: Option<BTreeMap<String, SimdEfficiency>>,
    /// GPU memory per path sample in flight.
    pub bytes_per_path: u64,
    /// GPU memory the render allocated, by category.
    pub memory: GpuMemory,
    /// Self-hits and depth-cut paths the shaders counted.
    pub failures: crate::numerics::Failures,
    /// The regenerating megakernel's persistent threads as launched (its `--threads`, default
    /// and rounding applied); None otherwise.
    pub threads: Option<u32>,
}
