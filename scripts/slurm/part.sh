#!/usr/bin/env bash
# One task of a split render: part K of N, K from Slurm's array index (or from the
# environment, when scripts/slurm/render.sh --local runs it).
#   part.sh NORI SCENE N OUTDIR [nori options...]
# Writes OUTDIR/part-K.exr (and .png). Threads: Slurm's --cpus-per-task, else NORI_THREADS,
# else 1. A task that finds its part's checkpoint (OUTDIR/part-K.checkpoint: it was
# preempted or killed and requeued) resumes from it.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
nori=$1 scene=$2 parts=$3 outdir=$4
shift 4
k=${SLURM_ARRAY_TASK_ID:?part.sh runs as a task of a Slurm job array (or under render.sh --local)}
threads=${SLURM_CPUS_PER_TASK:-${NORI_THREADS:-1}}
resume=()
if [ -f "$outdir/part-$k.checkpoint" ]; then
    resume=(--resume)
    echo "part $k of $parts: resuming from $outdir/part-$k.checkpoint"
fi
echo "part $k of $parts of $scene on $(hostname) with $threads threads"
exec "$nori" --no-progress "$scene" --part "$k/$parts" --threads "$threads" \
    -o "$outdir/part-$k" "${resume[@]}" "$@"
