#!/usr/bin/env bash
# Issue 25: the lockstep SIMD replay of every GPU method (naive megakernel, regenerating
# megakernel, wavefront per pass with waves and regenerating) at 8, 16, 32 and 64 lanes on the scenes the issue names, with
# the software driver's measured frame time of each method beside the predicted speed-ups.
# Written to experiments/results/<device>/simd_width/: per scene NAME.json/.txt (replay), NAME.svg
# (efficiency against width), NAME.times.json (llvmpipe frame seconds); summary.md for all; and
# replays without timings: sampled subsets (NAME-everyN) and the regenerating wavefront's tail.
# The experiment runner renders methods and cannot replay, hence a script. The replay needs no
# GPU; the timings are the software driver's (llvmpipe), not a GPU's.
# Usage: scripts/simd_width.sh [BIN] [OUT]
set -euo pipefail
BIN=${1:-target/release/wavetrace}
OUT=${2:-experiments/results/llvmpipe-2core/simd_width}
mkdir -p "$OUT"
W=8,16,32,64
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
NAMES=()
replay() { local name=$1; shift; nice -n 19 "$BIN" replay --simd-width "$W" --json "$OUT/$name.json" "$@" > "$OUT/$name.txt"; }
# Frame seconds of each method on the software driver, at the replay's settings (no counters).
times() {
  local name=$1; shift
  local m out=()
  for m in "megakernel --schedule waves" "megakernel --schedule regenerate" "wavefront --schedule waves" "wavefront --schedule regenerate"; do
    # shellcheck disable=SC2086
    nice -n 19 "$BIN" render "$@" --method $m --out "$TMP/img.exr" --report "$TMP/run.json" > /dev/null 2>&1
    out+=("$(jq -c --arg m "$m" '{method: $m, frame_seconds, wall_seconds, adapter: .adapter.name}' "$TMP/run.json")")
  done
  printf '%s\n' "${out[@]}" | jq -s . > "$OUT/$name.times.json"
}
scene() {
  local name=$1; shift
  NAMES+=("$name")
  replay "$name" --chart "$OUT/$name.svg" "$@"
  times "$name" "$@"
}
scene rtiow-final --scene rtiow-final --width 160 --height 90 --spp 64
scene cornell-nee --scene cornell --width 100 --height 100 --spp 64 --nee on
scene mesh-box-nee --scene tests/scenes/mesh_box.json --width 100 --height 100 --spp 64 --nee on
scene spheres-64 --scene spheres-64 --width 160 --height 90 --spp 64
# Seed 002's setting: 8 spheres tested in one loop (no BVH), 800x600.
scene spheres-8-brute --scene spheres-8 --accel none --width 800 --height 600 --spp 16
# The naive megakernel on one block in 16, the wavefront on one wave in 4 (the sampled subsets
# must give the same figures as the whole frame above).
replay spheres-8-brute-every16 --methods megakernel --scene spheres-8 --accel none --width 800 --height 600 --spp 16 --every 16
replay spheres-8-brute-every4 --methods wavefront --scene spheres-8 --accel none --width 800 --height 600 --spp 16 --every 4
# The regenerating wavefront with its megakernel tail (the default threshold: 5% of the pool),
# beside the same method without it in cornell-nee.json.
replay cornell-nee-tail --methods wavefront-regenerate --tail megakernel --scene cornell --width 100 --height 100 --spp 64 --nee on

# summary.md: per scene and method, replayed (predicted) figures beside llvmpipe's measured times.
{
  echo "# SIMD width: lockstep replay (predictions) beside llvmpipe's measured frame times"
  echo
  echo "Written by scripts/simd_width.sh. *Predicted*: from the CPU replay, no GPU (frame-level"
  echo "warp execution efficiency; speed-up = the naive megakernel's subgroup-iterations issued over"
  echo "the method's, the upper bound on an ideal W-lane machine). *Measured*: frame seconds on the"
  echo "software driver (8 lanes; the wavefront with its default atomic compaction; the regenerating"
  echo "megakernel with the driver's defaults, 2^16 threads run one subgroup at a time, where the replay"
  echo "predicts a GPU's: 2^18 threads, all resident). Speed-ups are over the naive megakernel."
  echo
  echo "| scene | method | eff. 8 | eff. 16 | eff. 32 | eff. 64 | predicted speed-up 8 | predicted speed-up 32 | measured llvmpipe frame s | measured speed-up (llvmpipe) |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for name in "${NAMES[@]}"; do
    jq -r --slurpfile t "$OUT/$name.times.json" --arg name "$name" '
      . as $r | ($t[0][0].frame_seconds) as $naive
      | ["megakernel", "regenerate", "wavefront", "wavefront-regenerate"] | to_entries[] | .key as $i | .value as $m
      | $r.methods[$m] as $x | ($t[0][$i].frame_seconds) as $s
      | def e(w): ($x.widths[w].simd.warp_execution_efficiency.efficiency * 100 * 100 | round / 100 | tostring) + "%";
        def p(w): ($x.widths[w].predicted_speedup_over_naive * 100 | round / 100 | tostring) + "x";
        "| \($name) | \($m) | \(e("8")) | \(e("16")) | \(e("32")) | \(e("64")) | \(p("8")) | \(p("32")) | \($s * 1000 | round / 1000) | \(($naive / $s) * 100 | round / 100)x |"
    ' "$OUT/$name.json"
  done
} > "$OUT/summary.md"
