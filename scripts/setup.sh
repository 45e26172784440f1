#!/usr/bin/env bash
# Builds wavetrace (release) and makes sure a Vulkan adapter exists: when `wavetrace info` finds
# none, installs Mesa's software Vulkan driver (lavapipe, Debian package mesa-vulkan-drivers).
# An OpenGL-only adapter does not count: Mesa's GL llvmpipe is on many machines without lavapipe,
# and it has no subgroups, so SIMD-efficiency measurements and their tests would go missing.
# Sourced by scripts/main.sh and scripts/test.sh; safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

# lavapipe's window-system code complains when this is unset; we render off-screen.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/xdg-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi

cargo build --release --locked

if ! WGPU_BACKEND=vulkan target/release/wavetrace info >/dev/null 2>&1; then
  echo "setup: no Vulkan adapter found; installing the software Vulkan driver (mesa-vulkan-drivers)" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq mesa-vulkan-drivers >/dev/null
  WGPU_BACKEND=vulkan target/release/wavetrace info >/dev/null || { WGPU_BACKEND=vulkan target/release/wavetrace info; exit 1; }
fi
target/release/wavetrace info | sed -n '1,/^chosen/p'
