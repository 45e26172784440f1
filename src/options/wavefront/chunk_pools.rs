//! `--chunk-pools`: the regenerating schedule's sample ring, in chunks of one pool of samples
//! (`gpu/wavefront/schedule.rs`).

use super::*;

/// Default `--chunk-pools`: the sample ring holds at most this many chunks of one pool of
/// samples each. Its per-sample radiance (16 bytes a sample) costs this many times the pool's
/// radiance; refills stop when it is full and its oldest chunk has paths still going.
pub const CHUNK_POOLS: u32 = 8;

/// Most chunks the sample ring may hold (`MAX_RING_CHUNKS` counters).
pub const MAX_CHUNK_POOLS: u32 = 1024;

flag! {
    /// Wavefront, --schedule regenerate: chunks of one pool of samples in the sample ring.
    /// Refills run at most this many chunks ahead of the oldest one not yet in the film (a
    /// larger ring waits less on its oldest chunk's longest paths); the ring takes 16 bytes a
    /// sample, within one storage binding.
    #[arg(long, default_value_t = CHUNK_POOLS, hide_short_help = true)]
    chunk_pools: u32
}

pub const KNOB: Knob = knob!("chunk_pools", "chunk-pools", WAVEFRONT, u32, o => o.wavefront.chunk_pools);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    in_range("chunk_pools", o.chunk_pools, 1, MAX_CHUNK_POOLS, " pools")
}

pub const RULE: Rule = Rule {
    knob: "chunk_pools",
    why: "sizes the regenerating sample ring",
    set: |o| number(o.chunk_pools != CHUNK_POOLS, o.chunk_pools),
    needs: regenerating,
};
