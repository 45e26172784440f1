//! How the wavefront keeps its queues dense (`--compaction on|off` and `--compaction-method` on
//! the command line, `cli/job.rs`; `compaction` in configs): atomic appends, a scan, or none.

use super::*;

/// How queues are kept dense.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Compaction {
    /// No queues: every pass runs over the whole pool, dead lanes idle.
    Off,
    /// Each pass appends surviving paths to the next queue with an atomic counter.
    #[default]
    Atomic,
    /// Passes mark each path's next queue; a stable prefix-sum scan builds the queue.
    Scan,
}
enum_values!(Compaction);

pub const KNOB: Knob = knob!("compaction", "compaction", WAVEFRONT, Compaction, o => o.wavefront.compaction);

/// Its pipeline constant (path_state.wgsl).
pub fn constant(o: &WavefrontOptions) -> (&'static str, f64) {
    ("COMPACTION", o.compaction as u32 as f64)
}
