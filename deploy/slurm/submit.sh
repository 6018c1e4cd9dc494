#!/usr/bin/env bash
# Queues render-array.sbatch and, to run after every element succeeded, merge.sbatch.
# Usage: SCENE=/shared/scene.glb WORK=/shared/render [SPP_PER_TASK=64] [TASKS=8] deploy/slurm/submit.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
export SCENE=${SCENE:-cornell} WORK=${WORK:-$PWD/caustic-render} SPP_PER_TASK=${SPP_PER_TASK:-64}
TASKS=${TASKS:-8}
export TOTAL_SPP=$((TASKS * SPP_PER_TASK))
render=$(sbatch --parsable --array="0-$((TASKS - 1))" --export=ALL "$here/render-array.sbatch")
render=${render%%;*}   # "jobid;cluster" on multi-cluster set-ups
merge=$(sbatch --parsable --dependency="afterok:$render" --kill-on-invalid-dep=yes --export=ALL "$here/merge.sbatch")
echo "render array job $render ($TASKS x $SPP_PER_TASK spp), merge job ${merge%%;*} -> $WORK/out/render.exr"
