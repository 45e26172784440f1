#!/usr/bin/env bash
# The device run, rehearsed on this machine (CI runs it): prepares .device/ and .gl/, copies only
# what the device tool would send (tracked files, untracked files git does not ignore, and the
# carried .device/ and .gl/), and in that copy runs scripts/device_figures.sh as the device
# session would, one call per group of steps, on the software driver at tiny size. Checks every
# limit of the device tool (its README in the tool library):
#   - the tracked tree is under 24 MiB, and what travels under 64 MiB;
#   - each call ends well inside 10 minutes (here: within WAVETRACE_DRY_RUN_CALL_LIMIT s);
#   - what a call leaves in $OUT comes back: at most 8 files, each under 16 MiB, 64 MiB in all,
#     no more than two folders down, names of letters, digits, '.', '_' and '-' only;
#   - every step wrote its archive, with a report (or the test log) in it.
# Prints each step's time.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=${WAVETRACE_DRY_RUN_CALL_LIMIT:-300}
bash scripts/device_prepare.sh >/dev/null

fail() { echo "device dry run: FAILED: $*" >&2; exit 1; }
mib() { awk -v b="$1" 'BEGIN { printf "%.1f MiB", b / 1048576 }'; }

tracked=$(git ls-files -z | xargs -0 stat -c %s | awk '{ s += $1 } END { print s + 0 }')
[ "$tracked" -lt $((24 * 1024 * 1024)) ] || fail "the tracked tree is $(mib "$tracked"), over 24 MiB"

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
tree="$stage/tree"
mkdir -p "$tree"
{ git ls-files -z; git ls-files -z --others --exclude-standard; } | tar --null -cf - -T - | tar -xf - -C "$tree"
for carried in .device .gl; do
  [ -e "$carried" ] && cp -r "$carried" "$tree/"
done
travels=$(du -sb "$tree" | cut -f1)
[ "$travels" -lt $((64 * 1024 * 1024)) ] || fail "what travels is $(mib "$travels"), over the 64 MiB limit"
echo "device dry run: tracked tree $(mib "$tracked"); travels $(mib "$travels") (binaries $(mib "$(du -sb .device | cut -f1)"))"

# The calls a session makes, in priority order (scripts/device_figures.sh --list).
calls=("tests dispatch-cost compute-passes warmup headline roulette" "megakernel-threads shading-cost material-kinds shader-checks simd simd-replay" "specialize intersect-cost decomposition pool-size scene-size regeneration" "regeneration-1080p queue-order" "refill regeneration-recheck" "bvh-layouts bvh-stack" "baselines seeds fixed-costs pool material workgroup" "megakernel-vs-wavefront")
export WAVETRACE_DEVICE_ALLOW_SOFTWARE=1 WAVETRACE_DEVICE_WORK="$stage/work"
n=0
for call in "${calls[@]}"; do
  n=$((n + 1))
  out="$stage/OUT$n"
  rm -rf "$out" && mkdir -p "$out"
  t0=$(date +%s)
  read -r -a steps <<<"$call"
  (cd "$tree" && timeout "$limit" bash scripts/device_figures.sh --scale tiny --out "$out" "${steps[@]}") ||
    fail "call $n ($call) failed or ran past $limit s; its log:$(echo; cat "$out/device.log" 2>/dev/null)"
  took=$(($(date +%s) - t0))
  # What the device tool would return from $OUT.
  files=$(find "$out" -type f | wc -l)
  [ "$files" -le 8 ] || fail "call $n leaves $files files in OUT; 8 come back"
  total=0
  while IFS= read -r -d '' f; do
    rel=${f#"$out"/}
    size=$(stat -c %s "$f")
    total=$((total + size))
    [ "$size" -le $((16 * 1024 * 1024)) ] || fail "$rel is $(mib "$size"), over 16 MiB"
    depth=$(tr -cd / <<<"$rel" | wc -c)
    [ "$depth" -le 2 ] || fail "$rel is more than two folders down"
    [[ "$rel" =~ ^[A-Za-z0-9._/-]+$ ]] || fail "$rel has a character the device tool does not return"
  done < <(find "$out" -type f -print0)
  [ "$total" -le $((64 * 1024 * 1024)) ] || fail "call $n returns $(mib "$total"), over 64 MiB"
  for step in "${steps[@]}"; do
    [ -f "$out/$step.tar.gz" ] || fail "call $n: no archive for step $step"
    want=report.json
    [ "$step" = tests ] && want=tests.log
    [ "$step" = dispatch-cost ] && want=dispatch_cost.json
    [ "$step" = intersect-cost ] && want=intersect_cost.rtiow-final.json
    listing=$(tar -tzf "$out/$step.tar.gz")
    grep -qx "./$want" <<<"$listing" || fail "$step.tar.gz holds no $want"
    if [ "$step" = dispatch-cost ]; then
      grep -qx "./bandwidth.json" <<<"$listing" || fail "$step.tar.gz holds no bandwidth.json"
    fi
  done
  echo "device dry run: call $n ($call): $took s, $files files, $(mib "$total")"
done
echo "device dry run: step times at tiny size on $(WGPU_BACKEND=vulkan .device/wavetrace info 2>/dev/null | sed -n 's/^chosen: \[[0-9]*\] //p' | cut -d: -f1):"
sed 's/^/  /' "$stage/work/step_seconds.txt"
echo "device dry run: passed"
