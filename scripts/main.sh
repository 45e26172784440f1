#!/usr/bin/env bash
# The main job: runs experiments/quick.json (CPU reference, megakernel and wavefront on small
# scenes, error against a cpu-f64 reference) on the best adapter. The report lands in
# out/quick/: report.html (open it in a browser), report.json, charts/, images/.
# Arguments are passed on to `wavetrace experiment run` (e.g. --out DIR, --shard I/N).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
target/release/wavetrace experiment run experiments/quick.json "$@"
