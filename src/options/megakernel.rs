//! The megakernel's options (`gpu/megakernel.rs`).

use super::{Schedule, DEFAULT_WORKGROUP_SIZE};

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, clap::Args)]
#[command(next_help_heading = "Megakernel")]
pub struct MegakernelOptions {
    /// Threads per workgroup (the seeds' block size): `--workgroup-size`, which the command line
    /// sets for both GPU methods.
    #[arg(skip = DEFAULT_WORKGROUP_SIZE)]
    pub workgroup_size: u32,
    /// Megakernel: most path samples in one GPU dispatch (bounds each dispatch's time under
    /// driver watchdogs).
    #[arg(long, default_value_t = DEFAULT_SAMPLES_PER_DISPATCH, hide_short_help = true)]
    pub samples_per_dispatch: u64,
    /// Dispatches per submission; the host waits (and updates progress) between submissions.
    #[arg(skip = DISPATCHES_PER_SUBMIT)]
    pub dispatches_per_submit: u32,
    /// One thread per sample (`waves`) or persistent threads that regenerate paths:
    /// `--schedule`, which the command line sets for both GPU methods.
    #[arg(skip = Schedule::Waves)]
    pub schedule: Schedule,
    /// Megakernel, --schedule regenerate: persistent threads per dispatch, rounded up to whole
    /// workgroups [default: 262144 on a discrete GPU, else 65536].
    #[arg(long, hide_short_help = true)]
    pub threads: Option<u32>,
    /// `regenerate` where the driver caps loops (llvmpipe): the paths a thread starts per launch
    /// at first (None: estimated from the scene, `gpu::megakernel::paths_per_thread`); lowered
    /// on a cut.
    #[arg(skip)]
    pub paths_per_thread: Option<u32>,
}

/// Default `--samples-per-dispatch`.
pub const DEFAULT_SAMPLES_PER_DISPATCH: u64 = 1 << 21;
const DISPATCHES_PER_SUBMIT: u32 = 16;

impl Default for MegakernelOptions {
    fn default() -> Self {
        Self {
            workgroup_size: DEFAULT_WORKGROUP_SIZE,
            samples_per_dispatch: DEFAULT_SAMPLES_PER_DISPATCH,
            dispatches_per_submit: DISPATCHES_PER_SUBMIT,
            schedule: Schedule::Waves,
            threads: None,
            paths_per_thread: None,
        }
    }
}

impl MegakernelOptions {
    /// `--schedule auto` made concrete ([`Schedule::Auto`]): the naive megakernel (`waves`) on
    /// every adapter. Other schedules stay as given.
    pub fn resolve(mut self) -> Self {
        if self.schedule == Schedule::Auto {
            self.schedule = Schedule::Waves;
        }
        self
    }
}
