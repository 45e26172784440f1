//! `--compute-passes`: how the wavefront groups its dispatches into compute passes (issue 42;
//! `gpu/wavefront/recorder.rs`).

use super::*;

/// How the wavefront groups its dispatches into compute passes (`--compute-passes`, issue 42).
/// In wgpu-core each compute pass becomes a command buffer of resource transitions spliced in
/// front of it, so a pass per dispatch pays that for each of a frame's thousands of dispatches;
/// `shared` (the default) lets consecutive dispatches share one pass until a copy or a
/// submission ends it. Set by measurement: on the NVIDIA H200 (release build of 50dcaad,
/// `experiments/results/nvidia-h200/compute_passes/`) sharing cut waves' rtiow-final
/// 1920x1080x64 frame from 1.23 s to 0.64 s and regenerate + tail's from 0.292 s to 0.243 s; on
/// llvmpipe the two are within noise. Barriers between dependent dispatches stay (wgpu orders each
/// dispatch's storage use within a pass too), so the film is the same. Per-pass timestamps need
/// a pass per dispatch: with `--timing passes` every dispatch keeps its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ComputePasses {
    /// One compute pass per dispatch.
    PerDispatch,
    /// Consecutive dispatches in one compute pass, up to the next copy or submission (where
    /// there are no per-pass timestamps).
    #[default]
    Shared,
}
enum_values!(ComputePasses);

flag! {
    /// Wavefront: one compute pass per dispatch, or consecutive dispatches sharing one (up to the
    /// next copy or submission; only where passes are not timed: with `--timing frame`).
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    compute_passes: ComputePasses
}

pub const KNOB: Knob =
    knob!("compute_passes", "compute-passes", WAVEFRONT, ComputePasses, o => o.wavefront.compute_passes);
