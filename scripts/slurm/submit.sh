#!/bin/bash
# Runs an experiment as a Slurm job array of N shards, then merges them:
#
#   scripts/slurm/submit.sh CONFIG OUT_DIR [N] [sbatch options...]
#   scripts/slurm/submit.sh experiments/baselines.json results/baselines 8 --partition=gpu --gres=gpu:1
#
# Shards go to OUT_DIR/shards/I, the merged report to OUT_DIR/merged. The merge waits for every
# task to succeed (--dependency=afterok): a shard with a failed run exits 1 and the merge is not
# started; submit that shard again (`--resume` runs its failed runs again) and merge by hand
# (`wavetrace experiment merge OUT_DIR/shards/* --out OUT_DIR/merged`), or merge what there is:
# runs no shard has are listed in the merged report's missing_runs.
# Options after N go to both submissions. SBATCH: the sbatch command [default: sbatch].
set -euo pipefail
cd "$(dirname "$0")/../.."

config=${1:?usage: scripts/slurm/submit.sh CONFIG OUT_DIR [N] [sbatch options...]}
out=${2:?usage: scripts/slurm/submit.sh CONFIG OUT_DIR [N] [sbatch options...]}
shards=${3:-8}
shift $(($# < 3 ? $# : 3))
case $shards in
  '' | *[!0-9]* | 0) echo "submit.sh: N must be a positive number of shards, got '$shards'" >&2; exit 2 ;;
esac
sbatch=${SBATCH:-sbatch}

array=$($sbatch --parsable --array="0-$((shards - 1))" "$@" scripts/slurm/shard.sbatch "$config" "$out/shards")
array=${array%%;*}   # --parsable prints JOBID or JOBID;CLUSTER
merge=$($sbatch --parsable --dependency="afterok:$array" "$@" scripts/slurm/merge.sbatch "$out/shards" "$out/merged")
echo "array job $array ($shards shards of $config), merge job ${merge%%;*} -> $out/merged"
