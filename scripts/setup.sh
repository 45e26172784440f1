#!/usr/bin/env bash
# Builds wavetrace (release) and makes sure a Vulkan adapter exists: when `wavetrace info` finds
# none, installs Mesa's software Vulkan driver (lavapipe, Debian package mesa-vulkan-drivers).
# Sourced by scripts/main.sh and scripts/test.sh; safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

# lavapipe's window-system code complains when this is unset; we render off-screen.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/xdg-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi

cargo build --release --locked

if ! target/release/wavetrace info >/dev/null 2>&1; then
  echo "setup: no GPU adapter found; installing the software Vulkan driver (mesa-vulkan-drivers)" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq mesa-vulkan-drivers >/dev/null
  target/release/wavetrace info >/dev/null || { target/release/wavetrace info; exit 1; }
fi
target/release/wavetrace info | sed -n '1,/^chosen/p'
