//! `--schedule`: how a GPU method hands path samples to its threads or slots. Both methods take
//! it; the wavefront's machinery is in `wavefront/schedule.rs`, the megakernel's loop in
//! `shaders/shared/regenerate.wgsl`.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Schedule {
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
