#!/usr/bin/env bash
# Issue 25: the lockstep SIMD replay of the naive megakernel at 8, 16, 32 and 64 lanes on the
# scenes the issue names, written to experiments/results/<device>/simd_width/ (no GPU needed).
# Usage: scripts/simd_width.sh [BIN] [OUT]
set -euo pipefail
BIN=${1:-target/ci/wavetrace}
OUT=${2:-experiments/results/llvmpipe-2core/simd_width}
mkdir -p "$OUT"
W=8,16,32,64
run() { local name=$1; shift; nice -n 19 "$BIN" replay --simd-width "$W" --json "$OUT/$name.json" "$@" > "$OUT/$name.txt"; }
run rtiow-final --scene rtiow-final --width 160 --height 90 --spp 64
run cornell-nee --scene cornell --width 100 --height 100 --spp 64 --nee on
run spheres-64 --scene spheres-64 --width 160 --height 90 --spp 64
# Seed 002's setting: 8 spheres tested in one loop (no BVH), 800x600; all blocks, then one
# block in 16 (the sampled subset must give the same figure).
run spheres-8-brute --scene spheres-8 --accel none --width 800 --height 600 --spp 16
run spheres-8-brute-every16 --scene spheres-8 --accel none --width 800 --height 600 --spp 16 --every 16
