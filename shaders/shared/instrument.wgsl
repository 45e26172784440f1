// Timing builds: instrumentation compiles to nothing. build.rs swaps this file for
// shared/instrument_on.wgsl to make the `--instrument` variant of every shader.

#include "shared/instrument_ids.wgsl"

fn instrument(pass_id: u32) {}
