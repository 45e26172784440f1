//! How the regenerating wavefront refills its pool (issue 26): at every iteration, into whatever
//! slots paths just left (the default), or in batches (`--refill-below F`: only once at most
//! F × pool paths are live, Cycles' rule of scheduling new work only when too few paths are left
//! to keep the device busy), optionally compacting the live states first (`--compact-states on`:
//! Cycles' `compact_states`, `shaders/wavefront/compact_states.wgsl`), so that a batch of
//! consecutive samples takes one contiguous run of slots, as a wave does.

/// The most live paths at which a refill runs: `below` × `pool`, rounded down (the whole pool at
/// 1, so every iteration refills).
pub fn refill_live(below: f64, pool: u32) -> u32 {
    (below * pool as f64).floor().clamp(0.0, pool as f64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refill_live_is_a_share_of_the_pool() {
        assert_eq!(refill_live(1.0, 1000), 1000);
        assert_eq!(refill_live(0.5, 1001), 500);
        assert_eq!(refill_live(1e-9, 1000), 0, "a tiny fraction refills only an empty pool");
    }
}
