#!/usr/bin/env bash
# wavetrace CPU reference vs Mitsuba 3 scalar_rgb on "three-spheres": same resolution, spp and
# max depth, one after the other on this machine. Prints both samples/s and ours/mitsuba.
#
# usage: benches/mitsuba/compare.sh [--width W] [--height H] [--spp N] [--max-depth D]
#            [--repeat R] [--mitsuba-threads T] [--out-dir DIR] [--skip-ours]
# --repeat R runs the pair R times (ours, mitsuba, ours, ...) and keeps each one's best run,
# which filters out interference from other work on the machine.
# Exit status: 0 when both ran, 1 when either failed (the other's figure is still printed).
set -euo pipefail

MITSUBA_VERSION=3.9.1   # the version the README's figures were taken with

W=400 H=225 SPP=640 DEPTH=50 REPEAT=1 MI_THREADS=0 OUT_DIR=/tmp/wavetrace-vs-mitsuba SKIP_OURS=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --width) W=$2; shift 2 ;;
    --height) H=$2; shift 2 ;;
    --spp) SPP=$2; shift 2 ;;
    --max-depth) DEPTH=$2; shift 2 ;;
    --repeat) REPEAT=$2; shift 2 ;;
    --mitsuba-threads) MI_THREADS=$2; shift 2 ;;
    --out-dir) OUT_DIR=$2; shift 2 ;;
    --skip-ours) SKIP_OURS=1; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
PY=${PYTHON:-python3}
mkdir -p "$OUT_DIR"

busy_cores() {  # cores kept busy by other work over one second, from /proc/stat
  local a b
  a=$(head -1 /proc/stat); sleep 1; b=$(head -1 /proc/stat)
  printf '%s\n%s\n' "$a" "$b" | awk -v n="$(nproc)" '
    { t = 0; for (i = 2; i <= 9; i++) t += $i; tot[NR] = t; idle[NR] = $5 + $6 }
    END { printf "%.2f", n * (1 - (idle[2] - idle[1]) / (tot[2] - tot[1])) }'
}
load_note() {  # a benchmark on a busy machine measures the other jobs too
  local busy; busy=$(busy_cores)
  echo "$busy" > "$2"
  echo "  before $1: $busy of $(nproc) cores busy with other work" >&2
  if awk -v b="$busy" 'BEGIN{exit !(b > 0.2)}'; then
    echo "  warning: the machine is not idle; figures may be low" >&2
  fi
}

# --- Mitsuba install --------------------------------------------------------------------------
if ! "$PY" -c "import mitsuba, numpy, sys; sys.exit(mitsuba.__version__ != '$MITSUBA_VERSION')" 2>/dev/null; then
  echo "installing mitsuba==$MITSUBA_VERSION and numpy" >&2
  "$PY" -m pip install --quiet "mitsuba==$MITSUBA_VERSION" numpy >&2
fi

echo "settings: ${W}x${H}, ${SPP} spp, max depth ${DEPTH} (rays per path), $(nproc) cores" >&2

# --- runs -------------------------------------------------------------------------------------
BIN="$ROOT/target/release/wavetrace"
if [[ $SKIP_OURS == 0 && ! -x $BIN ]]; then
  echo "building wavetrace (cargo build --release)" >&2
  (cd "$ROOT" && cargo build --release >&2) || true
fi
rm -f "$OUT_DIR"/wt.*.json "$OUT_DIR"/mitsuba.*.json "$OUT_DIR"/*.busy "$OUT_DIR/summary.json"

for ((i = 1; i <= REPEAT; i++)); do
  echo "run $i of $REPEAT" >&2
  if [[ $SKIP_OURS == 0 ]]; then
    if [[ -x $BIN ]]; then
      load_note wavetrace "$OUT_DIR/wt.$i.busy"
      "$BIN" render --scene three-spheres --method cpu --width "$W" --height "$H" --spp "$SPP" \
        --max-depth "$DEPTH" --out "$OUT_DIR/wt.exr" --png "$OUT_DIR/wt.png" \
        --report "$OUT_DIR/wt.$i.json" >&2 \
        || { echo "error: wavetrace render failed" >&2; rm -f "$OUT_DIR/wt.$i.json"; }
    else
      echo "error: no $BIN" >&2
    fi
  fi
  load_note mitsuba "$OUT_DIR/mitsuba.$i.busy"
  "$PY" "$HERE/three_spheres.py" --width "$W" --height "$H" --spp "$SPP" --max-depth "$DEPTH" \
    --threads "$MI_THREADS" --out "$OUT_DIR/mitsuba.exr" --png "$OUT_DIR/mitsuba.png" \
    > "$OUT_DIR/mitsuba.$i.json" \
    || { echo "error: mitsuba render failed" >&2; rm -f "$OUT_DIR/mitsuba.$i.json"; }
done

# --- summary -----------------------------------------------------------------------------------
"$PY" - "$OUT_DIR" "$REPEAT" "$SKIP_OURS" <<'PYEOF'
import json, os, sys
out, repeat, skip_ours = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "1"

def runs(prefix):
    got = []
    for i in range(1, repeat + 1):
        p = os.path.join(out, f"{prefix}.{i}.json")
        if os.path.exists(p) and os.path.getsize(p) > 0:
            r = json.load(open(p))
            r["_busy_before"] = float(open(os.path.join(out, f"{prefix}.{i}.busy")).read())
            got.append(r)
    return got

ours_runs, mi_runs = runs("wt"), runs("mitsuba")
ours = max(ours_runs, key=lambda r: r["samples_per_second"], default=None)
mi = max(mi_runs, key=lambda r: r["samples_per_second"], default=None)
summary = {"repeat": repeat, "ours": None, "mitsuba": None, "ratio_ours_over_mitsuba": None}
best = f"best of {len(ours_runs)}, " if repeat > 1 else ""
if ours:
    summary["ours"] = {
        "samples_per_second": ours["samples_per_second"],
        "wall_seconds": ours["wall_seconds"],
        "all_samples_per_second": [r["samples_per_second"] for r in ours_runs],
        "busy_cores_before": ours["_busy_before"],
    }
    print(f"wavetrace cpu       : {ours['samples_per_second']/1e6:8.3f} M samples/s  "
          f"({best}{ours['wall_seconds']:.2f} s)")
best = f"best of {len(mi_runs)}, " if repeat > 1 else ""
if mi:
    summary["mitsuba"] = {k: mi[k] for k in ("version", "samples_per_second", "seconds", "threads", "cpu_utilisation")}
    summary["mitsuba"]["all_samples_per_second"] = [r["samples_per_second"] for r in mi_runs]
    summary["mitsuba"]["busy_cores_before"] = mi["_busy_before"]
    print(f"mitsuba {mi['version']} scalar: {mi['samples_per_second']/1e6:8.3f} M samples/s  "
          f"({best}{mi['seconds']:.2f} s, {mi['threads']} threads, {mi['cpu_utilisation']:.2f} cores busy)")
if ours and mi:
    r = ours["samples_per_second"] / mi["samples_per_second"]
    summary["ratio_ours_over_mitsuba"] = r
    print(f"ratio ours/mitsuba  : {r:8.2f}x   (target >= 2x: {'met' if r >= 2 else 'NOT met'})")
elif not skip_ours:
    print("ratio ours/mitsuba  : n/a (a renderer failed)")
json.dump(summary, open(os.path.join(out, "summary.json"), "w"), indent=2)
sys.exit(0 if mi is not None and (ours is not None or skip_ours) else 1)
PYEOF
