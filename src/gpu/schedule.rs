//! `--schedule`: how a GPU method hands path samples to its threads or slots. Both methods take
//! it; the wavefront's machinery is in `wavefront/schedule.rs`, the megakernel's loop in
//! `shaders/shared/regenerate.wgsl`.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Schedule {
    /// The faster schedule as measured on the adapter's kind (README, "What it has found so
    /// far"): for the wavefront, `regenerate` with the megakernel tail on a GPU (on an H200 it
    /// beat waves, several times over, in all but two small jobs of `regeneration.json`) and
    /// `waves` on a software adapter (llvmpipe, where waves lead at 64 spp); for the
    /// megakernel, `waves` (the regenerating megakernel is slower on some H200 jobs). Resolved
    /// before a render starts ([`crate::method::MethodOptions::resolve`]); reports record what
    /// it chose. The command line's and experiment configs' default; the library's
    /// `Default` is `Waves`, the fixed baseline its tests compare against.
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
