//! What a GPU render measures besides its image, and how it is compiled: per-pass timestamps
//! or the frame's clock (`--timing`), wgpu's runtime shader checks (`--shader-checks`,
//! `gpu/shader_checks.rs`), shaders specialized to the scene (`--specialize`,
//! `gpu/specialize.rs`), and the preheat before the frame (`gpu/preheat.rs`).

/// How a GPU render is timed (`--timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Timing {
    /// A timestamp pair around every pass (where the adapter has timestamps): time per label,
    /// at the cost of a host wait whenever the query set fills (every 2048 passes).
    #[default]
    Passes,
    /// No timestamps: the host clock from each submission to its completion, under the label
    /// `frame`, and no waits beyond the method's own. Passes are still counted per label. The
    /// difference from `passes` is what the per-pass instrument costs.
    Frame,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShaderChecks {
    /// wgpu's default: bounds checks and bounded loops.
    #[default]
    Checked,
    /// No runtime checks: wgpu's trusted shader modules, without bounds checks or forced loop
    /// bounds.
    Unchecked,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Specialize {
    /// Only the kinds the scene has are compiled in.
    #[default]
    Scene,
    /// Every kind compiled in, whatever the scene has.
    None,
}

/// The preheat's default length: long enough for a GPU to raise its clocks from idle (NVIDIA
/// boosts within tens of milliseconds under full load), short beside a run's warm-up.
pub const DEFAULT_PREHEAT_SECONDS: f64 = 0.2;

/// The longest preheat a config or the command line may ask for.
pub const MAX_PREHEAT_SECONDS: f64 = 10.0;

/// Refuses a preheat outside `0..=MAX_SECONDS`.
pub fn check_preheat(seconds: f64) -> std::result::Result<(), String> {
    if !(0.0..=MAX_PREHEAT_SECONDS).contains(&seconds) {
        return Err(format!("the preheat must be 0 to {MAX_PREHEAT_SECONDS} seconds, got {seconds}"));
    }
    Ok(())
}
