#!/usr/bin/env bash
# Builds wavetrace and makes sure a Vulkan adapter exists: when `wavetrace info` finds none,
# installs Mesa's software Vulkan driver (lavapipe, Debian package mesa-vulkan-drivers).
# An OpenGL-only adapter does not count: Mesa's GL llvmpipe is on many machines without lavapipe,
# and it has no subgroups, so SIMD-efficiency measurements and their tests would go missing.
# Sourced by scripts/main.sh and scripts/test.sh, which share one build (the release profile,
# Cargo.toml): the tests compile only the crate's test binaries on top of the main job's build.
# Safe to run again. Sets WAVETRACE_BIN.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release --locked
WAVETRACE_BIN="target/release/wavetrace"
export WAVETRACE_BIN

if ! WGPU_BACKEND=vulkan "$WAVETRACE_BIN" info >/dev/null 2>&1; then
  echo "setup: no Vulkan adapter found; installing the software Vulkan driver (mesa-vulkan-drivers)" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers >/dev/null
  WGPU_BACKEND=vulkan "$WAVETRACE_BIN" info >/dev/null || { WGPU_BACKEND=vulkan "$WAVETRACE_BIN" info; exit 1; }
fi
"$WAVETRACE_BIN" info | sed -n '1,/^chosen/p'
