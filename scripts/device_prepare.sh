#!/usr/bin/env bash
# Prepares what a GPU machine without a toolchain needs, in .device/ and .gl/ (both ignored by
# git; name them in the device tool's `carry`):
#   .device/wavetrace   the stripped binary (release profile, the one build the tests share)
#   .device/suite       the stripped integration-test binary (scripts/device_figures.sh tests)
#   .device/BUILD       the commit and profile they were built from
#   .gl/*.deb           Debian's Vulkan loader and its neighbours, for a bare machine (the
#                       device README's recipe); skipped with WAVETRACE_DEVICE_LOADER=skip
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p .device
cargo build --release --locked
# The suite as scripts/test.sh builds it.
suite=$(cargo test --release --locked --no-run --message-format=json 2>/dev/null |
  sed -n 's/.*"executable":"\([^"]*\/suite-[^"]*\)".*/\1/p' | tail -n 1)
[ -n "$suite" ] || { echo "device_prepare.sh: the test build named no suite binary" >&2; exit 1; }
strip -o .device/wavetrace target/release/wavetrace
strip -o .device/suite "$suite"
{
  echo "commit $(git rev-parse HEAD)$(git diff --quiet HEAD -- . ':!experiments/results' || echo -dirty)"
  echo "profile release; built $(date -u +%Y-%m-%dT%H:%M:%SZ) by $(rustc --version)"
} > .device/BUILD
if [ "${WAVETRACE_DEVICE_LOADER:-download}" != skip ] && ! compgen -G ".gl/*.deb" >/dev/null; then
  mkdir -p .gl /tmp/amd64/partial
  o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
  if apt-get "${o[@]}" update -qq && (cd .gl && apt-get "${o[@]}" download -qq libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2); then
    echo "device_prepare.sh: Vulkan loader packages in .gl/"
  else
    echo "device_prepare.sh: could not download the loader packages (no apt or no network); a machine without libvulkan will need them" >&2
  fi
fi
du -sh .device .gl 2>/dev/null || true
