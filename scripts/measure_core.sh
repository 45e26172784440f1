#!/usr/bin/env bash
# Measures the renderer-core and wavefront figures quoted in the README and issue notes:
# rtiow-final with the CPU reference, the megakernel and the wavefront (timing runs), then
# instrumented runs for SIMD efficiency. Reports (JSON) and logs go to OUT_DIR.
#
#   scripts/measure_core.sh OUT_DIR [WIDTH HEIGHT SPP]
#   e.g. scripts/measure_core.sh experiments/results/llvmpipe-2core 1200 675 16
#        scripts/measure_core.sh experiments/results/nvidia-h100 1920 1080 64
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/measure_core.sh OUT_DIR [WIDTH HEIGHT SPP]}
w=${2:-1200}; h=${3:-675}; spp=${4:-16}
bin=${WAVETRACE_BIN:-target/release/wavetrace}
mkdir -p "$out" "$out/images"
render() { # name, extra args...
  local name=$1; shift
  echo "== $name" | tee -a "$out/log.txt"
  "$bin" render --scene rtiow-final --out "$out/images/$name.exr" --report "$out/$name.json" "$@" 2>&1 | tee -a "$out/log.txt"
}
"$bin" info > "$out/info.txt" 2>&1 || true
# Issue 2's comparison: CPU reference vs megakernel at 10 spp.
render cpu-10spp --method cpu --width "$w" --height "$h" --spp 10
render megakernel-10spp --method megakernel --width "$w" --height "$h" --spp 10
# Issue 3's comparison: megakernel vs wavefront knobs (timing runs carry no counters).
render megakernel --method megakernel --width "$w" --height "$h" --spp "$spp"
render wavefront-atomic --method wavefront --schedule waves --width "$w" --height "$h" --spp "$spp"
render wavefront-scan --method wavefront --schedule waves --compaction-method scan --width "$w" --height "$h" --spp "$spp"
render wavefront-nocompaction --method wavefront --schedule waves --compaction off --width "$w" --height "$h" --spp "$spp"
render wavefront-single-shade --method wavefront --schedule waves --shade single --width "$w" --height "$h" --spp "$spp"
# SIMD efficiency (instrumented: slower, not for timing), at a quarter of the pixels.
render megakernel-instrumented --method megakernel --instrument --width $((w / 2)) --height $((h / 2)) --spp "$spp"
render wavefront-instrumented --method wavefront --schedule waves --instrument --width $((w / 2)) --height $((h / 2)) --spp "$spp"
rm -rf "$out/images"
