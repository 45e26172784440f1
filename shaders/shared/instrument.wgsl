// Timing builds: instrumentation compiles to nothing. build.rs swaps this file for
// shared/instrument_on.wgsl to make the `--instrument` variant of every shader, and there fills
// the markers every instrumented entry point carries: `/*@subgroup_size_param*/` at the end of
// its parameters (a `@builtin(subgroup_size)` input, which only entry points can take) and
// `/*@subgroup_size_arg*/` in its first statement, `instrument_begin(/*@subgroup_size_arg*/);`.

#include "shared/instrument_ids.wgsl"

fn instrument_begin() {}

fn instrument(pass_id: u32) {}

fn instrument_traversal(first_slot: u32) {}

fn instrument_step(kind: u32) {}
