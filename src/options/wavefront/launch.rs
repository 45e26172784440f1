//! `--launch`: how the passes that consume a queue are launched (issue 42): the recorder sizes
//! their `Launch::Queue` (`gpu/wavefront/mod.rs`), the shaders read the constant.

use super::*;

/// How the passes that consume a queue (intersect, shade, shadow, the refill) are launched
/// (`--launch`, issue 42).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Launch {
    /// Sized on the GPU: a setup pass turns the queue's length into the pass's workgroup count,
    /// read by an indirect dispatch (vello's way).
    #[default]
    Indirect,
    /// At the pool's size (a wave's paths): threads past the queue's length return at once, as
    /// pbrt-v4's `ForAllQueued` launches its queues' largest size; no indirect arguments read.
    Pool,
}
enum_values!(Launch);

flag! {
    /// Wavefront: launch the passes that consume a queue (intersect, shade, shadow, the refill)
    /// with the workgroups a setup pass wrote from the queue's length (`indirect`), or at the
    /// pool's size, threads past the queue's length returning at once (`pool`, pbrt-v4's way).
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    launch: Launch
}

pub const KNOB: Knob = knob!("launch", "launch", WAVEFRONT, Launch, o => o.wavefront.launch);

/// Its pipeline constant (path_state.wgsl).
pub fn constant(o: &WavefrontOptions) -> (&'static str, f64) {
    ("LAUNCH_POOL", (o.launch == Launch::Pool) as u32 as f64)
}
