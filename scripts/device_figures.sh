#!/usr/bin/env bash
# The GPU figures in one command, for a machine with a GPU but no Rust toolchain or network:
# runs an already-built release binary over the experiment suite and packs every report, chart,
# HTML page and log into one archive, with the adapter and driver recorded (`wavetrace info`).
#
#   scripts/device_figures.sh OUT_DIR            full size (for a real GPU)
#   WAVETRACE_FIGURES_SCALE=tiny scripts/device_figures.sh OUT_DIR
#                                                every config shrunk to 32x18 and 1-2 spp: checks
#                                                the suite end to end on the software driver
#
# WAVETRACE_BIN picks the binary (default target/release/wavetrace); WAVETRACE_FIGURES_CONFIGS
# (names in experiments/, space-separated) runs a subset, as the test does. The archive is
# OUT_DIR.tar.gz; OUT_DIR keeps the same files unpacked. A config that fails is logged and the
# others go on; the exit status is non-zero if any failed.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/device_figures.sh OUT_DIR}
bin=${WAVETRACE_BIN:-target/release/wavetrace}
scale=${WAVETRACE_FIGURES_SCALE:-full}
case "$scale" in full | tiny) ;; *) echo "WAVETRACE_FIGURES_SCALE must be full or tiny, got $scale" >&2; exit 2 ;; esac
[ -x "$bin" ] || { echo "no binary at $bin (build it with cargo build --release, or set WAVETRACE_BIN)" >&2; exit 2; }
mkdir -p "$out/configs"
# Configs name scene files relative to themselves (fresnel.json: scenes/glass-block.json).
cp -r experiments/scenes "$out/configs/"
log="$out/log.txt"
: > "$log"
failed=0
say() { echo "== $*" | tee -a "$log"; }

"$bin" info > "$out/info.txt" 2>&1 || { echo "wavetrace info failed: no GPU adapter?" >&2; cat "$out/info.txt" >&2; exit 1; }
{ date -u +%Y-%m-%dT%H:%M:%SZ; uname -a; "$bin" --version; } > "$out/machine.txt" 2>&1

# The suite, as shipped; at tiny scale every size, sample count and repetition is shrunk (the
# questions stay, the figures mean nothing) so the whole script runs in minutes on llvmpipe.
# The numerical configs too: f32 on a GPU may contract to FMA or flush subnormals where
# llvmpipe does not, so where methods fail is worth measuring there as well.
read -r -a configs <<< "${WAVETRACE_FIGURES_CONFIGS:-quick megakernel_vs_wavefront regeneration baselines pool_memory material_cost nee light_sampling workgroup_size stability_scale stability_distance precision fresnel}"
for name in "${configs[@]}"; do
  src="experiments/$name.json"
  cfg="$out/configs/$name.json"
  if [ "$scale" = tiny ]; then
    sed -E -e 's/"resolutions": \[[^]]*\]/"resolutions": ["32x18"]/' \
      -e 's/"spp": \[[^]]*\]/"spp": [1, 2]/' \
      -e 's/"repetitions": [0-9]+/"repetitions": 1/' \
      -e 's/"warmup": [0-9]+/"warmup": 0/' \
      -e 's/("reference": \{[^}]*"spp": )[0-9]+/\116/' "$src" > "$cfg"
  else
    cp "$src" "$cfg"
  fi
  say "experiment $name ($scale)"
  if ! "$bin" experiment run "$cfg" --out "$out/$name" >> "$log" 2>&1; then
    say "FAILED: experiment $name (see above)"
    failed=1
  fi
done

# The seeds' headline case: rtiow-final at 1920x1080, 500 spp, depth 50, each GPU method.
if [ "$scale" = tiny ]; then size=(--width 32 --height 18 --spp 4); else size=(--width 1920 --height 1080 --spp 500); fi
mkdir -p "$out/rtiow_final_1080p"
# (--chunk-pools 64: a sample ring of 64 pools, 1 GiB at the default pool, waits less on its
# oldest chunk's longest paths; where bindings are smaller the ring is cut to fit.)
for run in "megakernel" "megakernel --schedule regenerate" "wavefront" "wavefront --schedule regenerate" "wavefront --schedule regenerate --tail megakernel" "wavefront --schedule regenerate --tail megakernel --chunk-pools 64"; do
  read -r -a args <<< "$run"
  tag=$(echo "$run" | sed -E 's/ --schedule /-/; s/ --tail /-tail-/; s/ --chunk-pools /-chunks-/')
  say "render rtiow-final $tag ${size[*]}"
  if ! "$bin" render --scene rtiow-final --method "${args[@]}" "${size[@]}" --max-depth 50 \
      --out "$out/rtiow_final_1080p/$tag.exr" --png "$out/rtiow_final_1080p/$tag.png" \
      --report "$out/rtiow_final_1080p/$tag.json" >> "$log" 2>&1; then
    say "FAILED: render $tag"
    failed=1
  fi
done
# EXRs of full-size runs are large and rebuilt from the reports' settings: keep PNGs and JSON.
find "$out" -name '*.exr' -delete

tar -czf "$out.tar.gz" -C "$(dirname "$out")" "$(basename "$out")"
say "archive: $out.tar.gz"
exit $failed
