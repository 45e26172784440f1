#!/usr/bin/env bash
# The main job: render Ray Tracing in One Weekend's final scene on the best adapter to
# out/final.exr, out/final.png and out/final.json. Arguments are passed on to `wavetrace render`
# (e.g. --spp 64 --width 1200 --height 675).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
mkdir -p out
target/release/wavetrace render --scene rtiow-final --method megakernel \
  --width 600 --height 338 --spp 16 \
  --out out/final.exr --png out/final.png --report out/final.json "$@"
