#!/usr/bin/env bash
# The test suite: sets up as scripts/setup.sh does, then runs every test with GPU tests
# required (a missing adapter fails them instead of skipping them). Tests build in the release
# profile, the main job's (Cargo.toml), so after scripts/main.sh only the test binaries compile.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
export WAVETRACE_REQUIRE_GPU=1
# A third-party EXR reader (the OpenEXR project's Python bindings, in a venv under target/) for
# tests/suite/exr_third_party.rs: our EXRs must read the same in it. On a fresh machine making the
# venv is mostly downloads (about 40 s), so it runs while the test binaries compile, which is the
# cores' work.
venv_out="${CARGO_TARGET_DIR:-target}/tmp/exr-venv.out"
mkdir -p "$(dirname "$venv_out")"
bash scripts/exr_reader.sh >"$venv_out" 2>"$venv_out.log" &
venv_pid=$!
cargo test --release --locked --no-run
if ! wait "$venv_pid"; then
  cat "$venv_out.log" >&2
  echo "test.sh: making the Python venv failed (scripts/exr_reader.sh)" >&2
  exit 1
fi
WAVETRACE_EXR_PYTHON=$(cat "$venv_out")
export WAVETRACE_EXR_PYTHON
# In-process GPU tests open Vulkan without the binary's main(), which is what turns Mesa's
# device-selection layer off on headless machines (src/gpu/headless.rs): do it for them.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then export NODEVICE_SELECT=${NODEVICE_SELECT:-1}; fi
# Checks an adapter could not run (tests/suite/common: `skipped`) are listed by name at the end,
# never counted silently as passed (cargo hides a passing test's output).
skipped="${CARGO_TARGET_DIR:-target}/tmp/skipped-checks.txt"
rm -f "$skipped"
# Twice as many test threads as cores: a GPU test waits while its device's queue runs, and the
# suite gives tests running at once devices of their own (tests/suite/common: up to two), so
# the other tests keep the cores busy (the suite with a cold shader cache on 2 cores: 402 s with
# two threads and one device, 361 s with four threads and two devices).
export RUST_TEST_THREADS=${RUST_TEST_THREADS:-$((2 * $(nproc)))}
status=0
cargo test --release --locked "$@" || status=$?
# Timing-sensitive tests (a competing load must flag a run, the same run alone must not) are
# #[ignore]d in the parallel run above, where the other tests load the cores too, and run here
# alone.
cargo test --release --locked --test suite -- --ignored --test-threads=1 || status=$?
# The Python package (issue 60): maturin builds the extension crate python/ into the EXR venv with
# the workspace's release profile and target directory (only pyo3, numpy and the crate compile on
# top of the build above: no second wgpu or naga), then pytest runs python/tests, which compare
# it with the binary ($WAVETRACE_BIN).
venv="$(dirname "$(dirname "$WAVETRACE_EXR_PYTHON")")"
if VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" maturin develop --release --quiet; then
  "$WAVETRACE_EXR_PYTHON" -m pytest -q python/tests || status=$?
else
  echo "the Python package did not build (maturin develop)" >&2
  status=1
fi
if [ -s "$skipped" ]; then
    echo "Checks skipped on this adapter ($(wc -l <"$skipped")):"
    sort -u "$skipped"
else
    echo "No checks skipped."
fi
exit "$status"
