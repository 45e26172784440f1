#!/usr/bin/env bash
# The test suite: sets up as scripts/setup.sh does, then runs every test with GPU tests
# required (a missing adapter fails them instead of skipping them).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
export WAVETRACE_REQUIRE_GPU=1
cargo test --release --locked "$@"
