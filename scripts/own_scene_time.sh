#!/usr/bin/env bash
# Times the README's "compare the methods on your own scene" commands as a new user runs them,
# in a scratch copy of experiments/: the exported Cornell box through experiments/my_scene.json
# (CPU reference, both megakernels, two wavefront schedules at 320x180x16 with NEE against a
# 256-spp cpu-f64 reference), and the cheap preset the README gives (4 spp, a 64-spp reference,
# one repetition). Prints each command and its wall time, the build and the machine, for
# experiments/results/<device>/own_scene/time.txt. WAVETRACE_BIN: the binary
# [default: target/release/wavetrace].
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${WAVETRACE_BIN:-target/release/wavetrace}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/experiments/scenes"
cp experiments/my_scene.json "$work/experiments/"
cp experiments/scenes/my_scene.json "$work/experiments/scenes/"
cd "$work"
echo "build: $("$bin" --version), commit $(git -C "$OLDPWD" rev-parse --short HEAD)$(git -C "$OLDPWD" diff --quiet HEAD -- src shaders || echo -dirty)"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "adapter: $("$bin" info 2>/dev/null | grep -m1 '^chosen:' | cut -d' ' -f3- || true)"
"$bin" scene export cornell >experiments/scenes/mine.json
run() {
  local name=$1; shift
  local start end
  start=$(date +%s.%N)
  "$bin" "$@" >"$name.log" 2>&1
  end=$(date +%s.%N)
  printf '%s: wavetrace %s\n  %.1f s (load average after: %s)\n' "$name" "$*" "$(awk "BEGIN{print $end - $start}")" \
    "$(cut -d' ' -f1-3 /proc/loadavg)"
}
run cheap experiment run experiments/my_scene.json --set 'scenes=["scenes/mine.json"]' --set 'spp=[4]' \
  --set reference.spp=64 --set repetitions=1 --out out/cheap
run default experiment run experiments/my_scene.json --set 'scenes=["scenes/mine.json"]' --out out/mine
