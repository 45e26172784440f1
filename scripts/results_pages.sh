#!/usr/bin/env bash
# Regenerates docs/results/<device>/<name>.md from every committed experiments/results/<device>/<name>/
# report.json (`wavetrace experiment report DIR --markdown --out FILE`). tests/suite/docs.rs fails
# when a committed page differs from what this writes. WAVETRACE_BIN: the binary
# [default: target/release/wavetrace].
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${WAVETRACE_BIN:-target/release/wavetrace}
for report in experiments/results/*/*/report.json; do
  dir=${report%/report.json}
  rest=${dir#experiments/results/}
  "$bin" experiment report "$dir" --markdown --out "docs/results/${rest%%/*}/${rest#*/}.md" >/dev/null
done
