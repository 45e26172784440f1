//! The megakernel's options (`gpu/megakernel.rs`).

use super::Schedule;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MegakernelOptions {
    /// Threads per workgroup (the seeds' block size).
    pub workgroup_size: u32,
    /// Most path samples per dispatch: bounds the time of one dispatch.
    pub samples_per_dispatch: u64,
    /// Dispatches per submission; the host waits (and updates progress) between submissions.
    pub dispatches_per_submit: u32,
    /// One thread per sample (`waves`) or persistent threads that regenerate paths.
    pub schedule: Schedule,
    /// `regenerate`: persistent threads per dispatch (None: [`default_threads`]).
    pub threads: Option<u32>,
    /// `regenerate` where the driver caps loops (llvmpipe): the paths a thread starts per launch
    /// at first (None: estimated from the scene, [`paths_per_thread`]); lowered on a cut.
    pub paths_per_thread: Option<u32>,
}

impl Default for MegakernelOptions {
    fn default() -> Self {
        Self {
            workgroup_size: 64,
            samples_per_dispatch: 1 << 21,
            dispatches_per_submit: 16,
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
