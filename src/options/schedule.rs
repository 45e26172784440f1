//! `--schedule`: how a GPU method hands path samples to its threads or slots. Both methods take
//! it; the wavefront's machinery is in `wavefront/schedule.rs`, the megakernel's loop in
//! `shaders/megakernel_regenerate.wgsl`.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Schedule {
    /// What measured faster on the adapter's kind: for the wavefront, `regenerate` with the
    /// megakernel tail on a GPU (it beat waves on the H200) and `waves` on a software adapter
    /// (llvmpipe, where waves lead); for the megakernel, `waves`, the seeds' one path per thread,
    /// kept as the baseline (the regenerating megakernel measured faster on every H200 job
    /// timed: ask for it by name to compare against the strongest megakernel). Resolved before a render starts; reports record what ran. The command
    /// line's and experiment configs' default.
    Auto,
    /// Paths start together and a thread or slot whose path ends idles until the wave or
    /// dispatch is over: the wavefront's waves of at most `pool` paths, the megakernel's one
    /// path per thread (the seeds' form).
    #[default]
    Waves,
    /// A thread or slot whose path ends takes the next sample at once (path regeneration): the
    /// wavefront refills its pool every iteration; the megakernel keeps a fixed set of threads
    /// that loop until the dispatch's samples are used up.
    Regenerate,
}

/// A schedule as it runs: `--schedule auto` made concrete, so code past resolution matches on
/// two cases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunSchedule {
    Waves,
    Regenerate,
}

impl From<RunSchedule> for Schedule {
    fn from(s: RunSchedule) -> Self {
        match s {
            RunSchedule::Waves => Schedule::Waves,
            RunSchedule::Regenerate => Schedule::Regenerate,
        }
    }
}
