#!/usr/bin/env bash
# The test suite: sets up as scripts/setup.sh does, then runs every test with GPU tests
# required (a missing adapter fails them instead of skipping them). Tests build in the `ci`
# profile (Cargo.toml): release optimisation, no link-time optimisation, one test binary.
set -euo pipefail
cd "$(dirname "$0")/.."
export WAVETRACE_PROFILE=ci
source scripts/setup.sh
export WAVETRACE_REQUIRE_GPU=1
# In-process GPU tests open Vulkan without the binary's main(), which is what turns Mesa's
# device-selection layer off on headless machines (src/gpu/headless.rs): do it for them.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then export NODEVICE_SELECT=${NODEVICE_SELECT:-1}; fi
cargo test --profile ci --locked "$@"
