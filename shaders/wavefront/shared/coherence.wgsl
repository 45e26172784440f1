// Timing builds: the coherence counters (issue 26) compile to nothing. The `--instrument`
// variant swaps in wavefront/shared/coherence_on.wgsl (build.rs), which needs the path pool and the
// SIMD counters, so only wavefront passes include this file, after both.

fn instrument_coherence(slot: u32, d: vec3<f32>) {}
