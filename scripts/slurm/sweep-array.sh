#!/bin/bash
# One shard of an e3d sweep per Slurm array task (docs/cluster.md).
#
#   N=8
#   JOB=$(sbatch --parsable --array=1-$N \
#         --export=ALL,SWEEP=scenes/sweeps/paper.ron,OUT=runs/paper,N=$N \
#         scripts/slurm/sweep-array.sh)
#   sbatch --dependency=afterok:$JOB --wrap "e3d merge runs/paper/shard-* --out runs/paper/merged"
#
# Environment: SWEEP (the sweep file), OUT (a folder; task K writes
# OUT/shard-K), N (the number of shards, default: the array's task count),
# E3D (the e3d binary, default: e3d on the PATH). A task that is requeued
# or rerun completes its shard (--resume) instead of starting again.
#SBATCH --job-name=e3d-sweep
#SBATCH --array=1-8
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=2
#SBATCH --output=e3d-sweep-%A_%a.log
set -euo pipefail
: "${SWEEP:?set SWEEP to the sweep file}"
: "${OUT:?set OUT to the output folder}"
: "${SLURM_ARRAY_TASK_ID:?run this script with sbatch --array=1-N}"
N="${N:-${SLURM_ARRAY_TASK_COUNT:?set N to the number of shards}}"
E3D="${E3D:-e3d}"
mkdir -p "$OUT"
exec "$E3D" sweep "$SWEEP" \
    --out "$OUT/shard-$SLURM_ARRAY_TASK_ID" \
    --shard "$SLURM_ARRAY_TASK_ID/$N" \
    --threads "${SLURM_CPUS_PER_TASK:-1}" \
    --resume
