#!/usr/bin/env bash
# The GPU figures, in bounded steps, for a GPU machine with no Rust toolchain and no network:
# the device tool's lent NVIDIA machine, or your own GPU. Runs an already-built, stripped
# binary (scripts/device_prepare.sh builds it into .device/) over GPU-only experiment configs.
# Each step runs under a time limit, continues what an earlier call left (--resume), and ends by
# writing one archive of compact results (report.json, runs.csv, passes.csv, charts, log; no
# images) to the output folder, so a call that is cut short still returns every finished step.
#
#   scripts/device_figures.sh [--scale full|tiny] [--out DIR] STEP...   run these steps in order
#   scripts/device_figures.sh --list                                    the steps, by priority
#
# Steps, in priority order (path samples at full size; the time is an estimate at an assumed
# 1e8 path samples/s at depth 50, about what waves reach on an H200, whose megakernels reach
# 1e9; each step's archive records how long it really took, and
# experiments/results/nvidia-h200/PROVENANCE.md the H200's step times):
#   tests               the integration test suite on this GPU (bit identity, agreement at its
#                       subgroup width), from the carried test binary       ~2 min
#   dispatch-cost       what one dispatch costs: a chain of 1000 tiny dispatches recorded six
#                       ways (a pass each or one pass, direct or indirect, read-write or
#                       read-only), 9 repetitions (wavetrace dispatch-cost); and what the
#                       memory delivers to a streaming pass, 256 MiB copied and read
#                       (wavetrace bandwidth)                                tiny   <1 min
#   compute-passes      the wavefront's dispatches in one compute pass each or sharing passes
#                       (--compute-passes), and regenerate + tail's host loop that never waits
#                       against one that waits for each check (--batches-in-flight 3, 1), and
#                       consumers launched at the pool's size (--launch pool), waves and
#                       regenerate + tail, rtiow-final and mesh-room at 1920x1080x64 NEE
#                       (device/compute_passes.json)                        10.7e9 ~3 min
#   shader-checks       wgpu's runtime shader checks on and off, every GPU method, rtiow-final
#                       and mesh-room at 1920x1080x64 NEE (device/shader_checks.json) 11e9 ~2 min
#   specialize          shaders with only the scene's kinds compiled in or every kind
#                       (--specialize scene|none), every GPU method, and regenerate + tail with
#                       shadow rays traced in shade (--shadow-rays inline) and with samples
#                       started where paths end (--refill in-place), rtiow-final and
#                       mesh-room at 1920x1080x64 NEE (device/specialize.json) 13.3e9 ~2 min
#   warmup              the warm-up itself: rtiow-final 1920x1080x16 NEE, the regenerating
#                       megakernel and regenerate + tail, each a fixed 15 s warm-up traced frame
#                       by frame with the GPU's clocks (device/warmup.json)  fixed  ~40 s
#   headline            rtiow-final and mesh-room at 1920x1080x64, both megakernels against
#                       the three wavefront schedules (device/headline.json) 5.3e9  ~1 min
#   roulette            the headline's scenes and methods with Russian roulette off and on
#                       (issue 46, the path-length axis; device/roulette.json): roulette off
#                       repeats the headline, on traces shorter paths       10.6e9 ~2 min
#   megakernel-threads  the regenerating megakernel's persistent threads, 65536 to 2097152,
#                       against the naive one: rtiow-final, cornell and spheres-100000 at
#                       1920x1080 x16 and x64, where it lost and won (issue 46;
#                       device/megakernel_threads.json; megakernels only)  9.9e9  ~2 min
#   shading-cost        rtiow-heavy-1 to -16 and rtiow-final (the cost's zero) at 1920x1080x16
#                       NEE, both megakernels against the wavefront schedules and a single
#                       shade pass (issue 46; device/shading_cost.json)      4.8e9  ~2 min
#   material-kinds      rtiow-kinds-1 to -8 (K distinct costly patterns) and rtiow-final at
#                       1920x1080x16 NEE,
#                       both megakernels against the wavefront schedules with a shade pass per
#                       material kind, per pattern (--shade per-texture) and a single one
#                       (issue 46; device/material_kinds.json)               4.6e9  ~2 min
#   decomposition       rtiow-final 1920x1080x64 NEE cut at depth 1, 2, 4 and 50: the same rays
#                       in both megakernels, waves and regenerate + tail, so depth 1 isolates the
#                       wavefront's own cost (issue 44; device/decomposition.json) 8.5e9  ~2 min
#   intersect-cost      the wavefront's intersect of rtiow-final's and mesh-room's 1920x1080x64
#                       camera rays against a twin that keeps each ray in registers and writes
#                       no path state, 6 rounds of each (issue 44; wavetrace intersect-cost)
#                                                                 1.6e9 at depth 1 <1 min
#   pool-size           waves and regenerate + tail with pools of 262144 to 4194304 paths,
#                       rtiow-final and mesh-room at 1920x1080x64 NEE (issue 44: Cycles' rule
#                       gives ~4.3 M on an H200; device/pool_size.json)       8.5e9  ~2 min
#   scene-size          a generated terrain of 10^4 to 10^7 triangles (triangles-N) at
#                       1920x1080x16, the regenerating megakernel against waves and regenerate +
#                       tail, with each render's BVH build (issue 46; device/scene_size.json;
#                       about 5 s of host BVH build per render of the largest) 1.6e9  ~3 min
#   bvh-layouts         the BVH layouts (--bvh binary|aila-laine|wide), both megakernels, waves
#                       and regenerate + tail, rtiow-final, mesh-room and triangles-1000000 at
#                       1920x1080x16 NEE (issue 59; device/bvh_layouts.json; about 1 s of
#                       host BVH build per render of the terrain)            9.9e9  ~3 min
#   bvh-stack           the traversal stack (--stack function|workgroup) with the binary and
#                       wide layouts, both megakernels, waves and regenerate + tail, mesh-room
#                       and triangles-1000000 at 1920x1080x16 NEE (issue 59; device/bvh_stack.json:
#                       the faster sets --stack's default on GPUs)           8.8e9  ~3 min
#   simd                SIMD efficiency at the device's width, 4 scenes, every GPU method
#                       (device/simd.json, instrumented)                     0.15e9 <1 min
#   simd-replay         every GPU method's device counters (--instrument) beside the CPU
#                       lockstep replay at the device's subgroup width (issue 25), 4 scenes
#                       (report.json: both, per slot; comparison.md)        tiny   <1 min
#   regeneration-recheck  regeneration.json's rtiow-final and spheres-100000 cells again, warm
#                       and interleaved, 5 repetitions (device/regeneration_recheck.json: the
#                       first H200 run of regeneration.json was cold)      8.3e9  ~2 min
#   regeneration        regeneration.json (160x90 to 1200x675, 4 to 64 spp)  6.1e9  ~1-2 min
#   regeneration-1080p  1920x1080 at 16 and 64 spp (device/regeneration_1080p.json)
#                                                                            13.3e9 ~2-3 min
#   queue-order         arrival against slot queue order, keyed by depth or not (issue 26),
#                       waves and regenerate + tail, 5 scenes at 1920x1080 x16 and x64
#                       (device/queue_order.json)                            40e9   ~6-7 min
#   refill              batched refills and state compaction (issue 26: --refill-below,
#                       --compact-states) and the ray sort (--ray-sort) against
#                       regenerate + tail's defaults and waves, 5 scenes at 1920x1080 x16
#                       and x64 (device/refill.json)                         37e9  ~6-7 min
#   baselines           baselines.json (1280x720 and 1080p, NEE, threads sweep) 5.8e9 ~1 min
#   seeds               rtiow-final 1920x1080x500, each GPU method once      5.2e9  ~1 min
#   fixed-costs         queue appends per lane against per subgroup, rtiow-final and mesh-room
#                       at 1920x1080x16, and the scan compaction (device/fixed_costs.json) 1.5e9 <1 min
#   pool                pool_memory.json                                     1.6e9  <1 min
#   material            material_cost.json                                   1.5e9  <1 min
#   workgroup           workgroup_size.json                                  1.4e9  <1 min
#   megakernel-vs-wavefront  megakernel_vs_wavefront.json (4096-spp megakernel references)
#                                                                            56e9   ~9 min+
# On the software driver at --scale tiny (every size 32x18 at 1-2 spp, the 10^7-triangle terrain
# at 2x10^5, over llvmpipe's 128 MiB bindings, and the 10^6 one at 2x10^4, whose BVH build would
# dominate, as the dry run runs them)
# each step takes seconds; the dry run prints the times (scripts/device_dry_run.sh).
#
# With the device tool (docs/device-tool.md): prepare here, then one call per group of
# steps, each call well inside the tool's 10 minutes:
#   scripts/device_prepare.sh                     # .device/ (binaries) and .gl/ (Vulkan loader)
#   run(command="bash scripts/device_figures.sh --out $OUT tests dispatch-cost compute-passes warmup headline",
#       carry=[".device", ".gl"], timeout_s=600)
# and commit what comes back (files_at/*.tar.gz) under experiments/results/<device>/.
#
# Environment:
#   WAVETRACE_BIN                   the binary [.device/wavetrace, else target/release/wavetrace]
#   WAVETRACE_DEVICE_WORK           where steps keep their reports between calls, for --resume
#                                   [$HOME/wavetrace-device]
#   WAVETRACE_DEVICE_BUDGET         seconds this call may spend on steps [540]; a step is given
#                                   what is left, and none starts with under 60 s left
#   WAVETRACE_DEVICE_ALLOW_SOFTWARE 1: accept a software adapter (the dry run); otherwise only a
#                                   discrete GPU on Vulkan is accepted
set -uo pipefail
cd "$(dirname "$0")/.."

steps_table() {
  cat <<'EOF'
tests
dispatch-cost
compute-passes device/compute_passes.json
shader-checks device/shader_checks.json
specialize device/specialize.json
warmup device/warmup.json
headline device/headline.json
roulette device/roulette.json
megakernel-threads device/megakernel_threads.json
shading-cost device/shading_cost.json
material-kinds device/material_kinds.json
decomposition device/decomposition.json
intersect-cost
pool-size device/pool_size.json
scene-size device/scene_size.json
bvh-layouts device/bvh_layouts.json
bvh-stack device/bvh_stack.json
simd device/simd.json
simd-replay
regeneration-recheck device/regeneration_recheck.json
regeneration regeneration.json
regeneration-1080p device/regeneration_1080p.json
queue-order device/queue_order.json
refill device/refill.json
baselines baselines.json
seeds device/seeds_1080p.json
fixed-costs device/fixed_costs.json
pool pool_memory.json
material material_cost.json
workgroup workgroup_size.json
megakernel-vs-wavefront megakernel_vs_wavefront.json
EOF
}
config_of() { steps_table | awk -v s="$1" '$1 == s { print $2; found = 1 } END { exit !found }'; }

scale=full
out=${OUT:-out/device}
steps=()
while [ $# -gt 0 ]; do
  case "$1" in
    --list) steps_table | awk '{ printf "%-24s %s\n", $1, ($2 != "" ? "experiments/" $2 : $1 == "tests" ? "(test suite)" : $1 == "dispatch-cost" ? "(wavetrace dispatch-cost)" : $1 == "intersect-cost" ? "(wavetrace intersect-cost)" : "(render + replay)") }'; exit 0 ;;
    --scale) scale=${2:?--scale needs full or tiny}; shift 2 ;;
    --out) out=${2:?--out needs a directory}; shift 2 ;;
    -h | --help) sed -n '2,/^set -uo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "device_figures.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) config_of "$1" >/dev/null || { echo "device_figures.sh: unknown step '$1' (see --list)" >&2; exit 2; }
       steps+=("$1"); shift ;;
  esac
done
case "$scale" in full | tiny) ;; *) echo "device_figures.sh: --scale must be full or tiny, got $scale" >&2; exit 2 ;; esac
[ ${#steps[@]} -gt 0 ] || { echo "device_figures.sh: name the steps to run (see --list)" >&2; exit 2; }
# The device tool returns at most 8 files a call: one archive a step, the log and info.txt.
[ ${#steps[@]} -le 6 ] || { echo "device_figures.sh: at most 6 steps a call (8 files come back)" >&2; exit 2; }

bin=${WAVETRACE_BIN:-}
if [ -z "$bin" ]; then
  if [ -x .device/wavetrace ]; then bin=.device/wavetrace; else bin=target/release/wavetrace; fi
fi
[ -x "$bin" ] || { echo "device_figures.sh: no binary at $bin (scripts/device_prepare.sh builds .device/wavetrace, or set WAVETRACE_BIN)" >&2; exit 2; }
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
work=${WAVETRACE_DEVICE_WORK:-$HOME/wavetrace-device}
budget=${WAVETRACE_DEVICE_BUDGET:-540}
mkdir -p "$out" "$work"
log="$out/device.log"
: > "$log"
say() { echo "== $*" | tee -a "$log"; }
started=$(date +%s)

# 1. The Vulkan loader: a bare machine has none; the carried .gl/ holds Debian's packages.
if ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; then
  if compgen -G ".gl/*.deb" >/dev/null; then
    say "unpacking the carried Vulkan loader (.gl/)"
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
  else
    say "no Vulkan loader here and none carried (.gl/): scripts/device_prepare.sh downloads it"
  fi
fi

# 2. The adapter: Vulkan only (an OpenGL adapter runs the megakernel but not the wavefront's
# twenty storage buffers), and a discrete GPU unless the dry run allows a software one.
export WGPU_BACKEND=vulkan
export NODEVICE_SELECT=${NODEVICE_SELECT:-1}
info=$("$bin" info 2>&1)
if ! grep -q "device type: *DiscreteGpu" <<<"$info" && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  info=$("$bin" info 2>&1)
fi
echo "$info" | tee "$out/info.txt" >>"$log"
type=$(sed -n 's/^ *device type: *//p' <<<"$info")
backend=$(sed -n 's/^ *backend: *//p' <<<"$info")
say "adapter: $(sed -n 's/^chosen: \[[0-9]*\] //p' <<<"$info" | cut -d: -f1) | vendor $(sed -n 's/^ *vendor: *//p' <<<"$info") | type ${type:-?} | backend ${backend:-?} | driver $(sed -n 's/^ *driver: *//p' <<<"$info")"
if [ "$backend" != Vulkan ]; then
  say "REFUSED: the chosen adapter is not on Vulkan (backend '${backend:-none}'); see info.txt"
  exit 1
fi
if [ "$type" != DiscreteGpu ] && [ "${WAVETRACE_DEVICE_ALLOW_SOFTWARE:-0}" != 1 ]; then
  say "REFUSED: the chosen adapter is a '${type:-?}', not a discrete GPU (WAVETRACE_DEVICE_ALLOW_SOFTWARE=1 accepts it)"
  exit 1
fi
{ date -u +%Y-%m-%dT%H:%M:%SZ; uname -a; "$bin" --version; cat .device/BUILD 2>/dev/null; } > "$work/machine.txt" 2>&1

# Configs are used from a copy beside the scenes they name (relative paths), shrunk at tiny
# scale (the questions stay, the figures mean nothing; a timed warm-up of at most two frames).
configs="$work/configs"
rm -rf "$configs"
mkdir -p "$configs/device"
cp -r experiments/scenes "$configs/"
for src in experiments/*.json experiments/device/*.json; do
  rel=${src#experiments/}
  case "$rel" in report.schema.json) continue ;; esac
  if [ "$scale" = tiny ]; then
    sed -E -e 's/"resolutions": \[[^]]*\]/"resolutions": ["32x18"]/' \
      -e 's/"spp": \[[^]]*\]/"spp": [1, 2]/' \
      -e 's/"warmup": [0-9]+,?//' -e 's/"warmup": \{[^}]*\},?//' \
      -e 's/"repetitions": [0-9]+/"repetitions": 1, "warmup": {"max_frames": 2}/' \
      -e 's/"triangles-10000000"/"triangles-200000"/' -e 's/"triangles-1000000"/"triangles-20000"/' \
      -e 's/("reference": \{[^}]*"spp": )[0-9]+/\116/' "$src" > "$configs/$rel"
  else
    cp "$src" "$configs/$rel"
  fi
done

# One archive per step, of compact files only, under 16 MiB (what the device tool returns).
pack() {
  local step=$1 dir=$work/$1
  cp "$work/machine.txt" "$out/info.txt" "$dir/" 2>/dev/null
  (cd "$dir" && find . -maxdepth 2 \( -name '*.json' -o -name '*.csv' -o -name '*.svg' -o -name '*.txt' -o -name '*.log' -o -name '*.md' \) \
    ! -path './images/*' ! -path './references/*' -print0 | sort -z | tar --null -czf "$out/$step.tar.gz" -T -)
  local size
  size=$(stat -c %s "$out/$step.tar.gz")
  if [ "$size" -gt $((16 * 1024 * 1024)) ]; then
    say "FAILED: $step.tar.gz is $size bytes, over the 16 MiB a file the device tool returns"
    return 1
  fi
  say "archive: $step.tar.gz ($size bytes)"
}

failed=0
for step in "${steps[@]}"; do
  left=$((budget - ($(date +%s) - started)))
  if [ "$left" -lt 60 ]; then
    say "NOT STARTED: $step ($left s left of this call's $budget s); run it in the next call"
    failed=1
    continue
  fi
  dir="$work/$step"
  # A step's archive carried back from an earlier machine seeds its resume.
  if [ ! -f "$dir/report.json" ] && [ -f ".device/results/$step.tar.gz" ]; then
    mkdir -p "$dir" && tar -xzf ".device/results/$step.tar.gz" -C "$dir"
    say "resuming $step from the carried .device/results/$step.tar.gz"
  fi
  mkdir -p "$dir"
  t0=$(date +%s)
  say "step $step ($scale, up to $left s)"
  if [ "$step" = tests ]; then
    suite=.device/suite
    if [ ! -x "$suite" ]; then
      say "FAILED: tests: no test binary at $suite (scripts/device_prepare.sh builds it)"
      failed=1
    else
      # At tiny scale, the regenerating megakernel's tests stand for the suite. Skipped
      # everywhere: the suite's device-run test (it would run this script inside itself) and
      # the repository's size (the copy that travels has no .git; it is checked before it
      # travels).
      filter=(--skip device_ --skip repository::)
      if [ "$scale" = tiny ]; then filter=(megakernel::regenerate "${filter[@]}"); fi
      mkdir -p "$dir/tmp"
      WAVETRACE_TEST_ROOT=$PWD WAVETRACE_TEST_BIN=$bin WAVETRACE_TEST_TMP=$dir/tmp WAVETRACE_REQUIRE_GPU=1 \
        timeout --kill-after=10 "$left" "$suite" "${filter[@]}" > "$dir/tests.log" 2>&1
      rc=$?
      rm -rf "$dir/tmp"
      grep -E '^test result|^failures:|^    [a-z_:]+$|panicked' "$dir/tests.log" | tee -a "$log"
      [ $rc = 0 ] || { say "FAILED: tests (exit $rc; tests.log in the archive)"; failed=1; }
    fi
  elif [ "$step" = dispatch-cost ]; then
    # Issue 42: the floor under the wavefront's time between passes (src/gpu/dispatch_cost.rs).
    n=(--dispatches 1000 --repetitions 9)
    [ "$scale" = tiny ] && n=(--dispatches 16 --repetitions 2)
    timeout --kill-after=10 "$left" "$bin" dispatch-cost "${n[@]}" --json "$dir/dispatch_cost.json" \
      > "$dir/step.log" 2>&1
    rc=$?
    # Issue 44: what the device's memory delivers to a streaming pass (src/gpu/bandwidth.rs), the
    # floor the passes' achieved bandwidth (state_traffic) is read against. Tiny: 4 MiB.
    b=(--repetitions 9)
    [ "$scale" = tiny ] && b=(--mib 4 --repetitions 2)
    timeout --kill-after=10 "$left" "$bin" bandwidth "${b[@]}" --json "$dir/bandwidth.json" \
      >> "$dir/step.log" 2>&1
    brc=$?
    [ $rc = 0 ] && rc=$brc
    tee -a "$log" < "$dir/step.log" | tail -n 14
    [ $rc = 0 ] || { say "FAILED: dispatch-cost or bandwidth (exit $rc; step.log in the archive)"; failed=1; }
  elif [ "$step" = intersect-cost ]; then
    # Issue 44, item 1b: intersect's traversal apart from its state traffic (src/gpu/intersect_cost.rs).
    n=(--width 1920 --height 1080 --spp 64 --repetitions 5)
    [ "$scale" = tiny ] && n=(--width 32 --height 18 --spp 2 --repetitions 1)
    rc=0
    : > "$dir/step.log"
    for sc in rtiow-final:rtiow-final mesh-room:experiments/scenes/mesh-room.json; do
      timeout --kill-after=10 "$left" "$bin" intersect-cost --scene "${sc#*:}" "${n[@]}" \
        --json "$dir/intersect_cost.${sc%%:*}.json" >> "$dir/step.log" 2>&1 || rc=$?
    done
    tee -a "$log" < "$dir/step.log" | tail -n 10
    [ $rc = 0 ] || { say "FAILED: intersect-cost (exit $rc; step.log in the archive)"; failed=1; }
  elif [ "$step" = simd-replay ]; then
    # Issue 25: the device's counters against the replay at the device's width (32 lanes on
    # NVIDIA), every GPU method on the same frames; report.json holds both per scene, per method,
    # per slot, and simd_replay_compare.py prints them side by side. The wavefronts use the scan
    # (a deterministic queue order the replay follows) and a pool of 32,768 so the regenerating
    # one refills 7 times, in the order `auto` gives both (slot order, 7 pools). The
    # regenerating megakernel runs 16,384 threads (about 14 samples each at full size); its
    # sample hand-out is the GPU scheduler's, and the replay assumes every subgroup resident,
    # taking samples in turn (a GPU's case). On llvmpipe (the dry run) it runs one workgroup of
    # 64 threads, as tests/suite/simd_replay.rs does, so llvmpipe's worker threads do not
    # interleave the hand-out: one subgroup at a time, each thread up to its loop limit's
    # paths, and the replay is told so.
    sg=$(sed -n 's/^ *subgroups: *yes, size \([0-9]*\)\.\.=\([0-9]*\).*/\1 \2/p' <<<"$info")
    read -r sg_min sg_max <<<"$sg"
    size=(--width 160 --height 90 --spp 16)
    [ "$scale" = tiny ] && size=(--width 32 --height 18 --spp 2)
    wf=(--compaction-method scan --pool-size 32768)
    regen=(--threads 16384)
    grep -q llvmpipe <<<"$info" && regen=(--threads 64 --resident-subgroups 1 --paths-per-thread llvmpipe)
    rc=0
    if [ -z "$sg_min" ] || [ "$sg_min" != "$sg_max" ]; then
      say "FAILED: simd-replay: the device's subgroup width is not one fixed size ($sg)"; rc=1
    else
      echo '{' > "$dir/report.json"
      sep=
      for sc in "rtiow-final --nee off" "cornell --nee on" "spheres-64 --nee off" "spheres-8 --nee off"; do
        read -r name nee_flag nee <<<"$sc"
        device=
        for m in "megakernel --method megakernel --schedule waves" \
                 "regenerate --method megakernel --schedule regenerate ${regen[*]:0:2}" \
                 "wavefront --method wavefront --schedule waves ${wf[*]}" \
                 "wavefront-regenerate --method wavefront --schedule regenerate ${wf[*]}"; do
          read -r label args <<<"$m"
          # shellcheck disable=SC2086 # $args is a list of flags
          timeout --kill-after=10 "$left" "$bin" render --scene "$name" $args --instrument "${size[@]}" \
            $nee_flag "$nee" --out "$dir/$name.exr" --report "$dir/$name.$label.json" >> "$dir/step.log" 2>&1 || rc=$?
          device="$device${device:+,}\"$label\": $(cat "$dir/$name.$label.json" 2>/dev/null || echo null)"
          rm -f "$dir/$name.exr" "$dir/$name.$label.json"
        done
        timeout --kill-after=10 "$left" "$bin" replay --scene "$name" "${size[@]}" $nee_flag "$nee" "${wf[@]}" \
          "${regen[@]}" --simd-width "$sg_min" --json "$dir/$name.replay.json" >> "$dir/step.log" 2>&1 || rc=$?
        printf '%s"%s": {"device": {%s}, "replay": %s}\n' "$sep" "$name" "$device" \
          "$(cat "$dir/$name.replay.json" 2>/dev/null || echo null)" >> "$dir/report.json"
        rm -f "$dir/$name.replay.json"
        sep=,
      done
      echo '}' >> "$dir/report.json"
      python3 scripts/simd_replay_compare.py "$dir/report.json" > "$dir/comparison.md" 2>> "$dir/step.log" || rc=$?
      tail -n 4 "$dir/comparison.md" | tee -a "$log"
    fi
    tail -n 3 "$dir/step.log" | tee -a "$log"
    [ $rc = 0 ] || { say "FAILED: simd-replay (exit $rc; step.log in the archive)"; failed=1; }
  else
    cfg="$configs/$(config_of "$step")"
    timeout --kill-after=10 "$left" "$bin" experiment run "$cfg" --out "$dir" --resume \
      --cache "$work/cache" > "$dir/step.log" 2>&1
    rc=$?
    tail -n 3 "$dir/step.log" | tee -a "$log"
    case $rc in
      0) ;;
      124 | 137) say "CUT SHORT: $step at the call's time limit; the same command resumes it (finished runs are kept)"; failed=1 ;;
      *) say "FAILED: $step (exit $rc; step.log in the archive)"; failed=1 ;;
    esac
  fi
  echo "$step $scale $(($(date +%s) - t0))" >> "$work/step_seconds.txt"
  cp "$work/step_seconds.txt" "$dir/"
  say "step $step took $(($(date +%s) - t0)) s"
  pack "$step" || failed=1
done
say "done in $(($(date +%s) - started)) s"
exit $failed
