#!/usr/bin/env bash
# Splits a render over a Slurm job array and merges it: one array task a part (nori
# --part K/N), then a merge job that runs once every task has succeeded.
#
#   scripts/slurm/render.sh SCENE.xml --parts N [--spp S] [--out STEM] [--nori PATH]
#       [--tasks LIST] [--local] [sbatch options...] [-- nori options...]
#
#   --parts N     split every pixel's samples into N parts, one array task each
#   --spp S       samples per pixel of the whole render (default: the scene's sampler)
#   --out STEM    write STEM.exr and STEM.png (default: the scene's path without .xml);
#                 the parts and logs go to STEM_parts/
#   --nori PATH   the nori program (default: build/nori beside this script's repository);
#                 it must be at the same path on the compute nodes (a shared file system)
#   --tasks LIST  submit only these parts (Slurm array syntax: 3 or 2,5 or 1-4) and a new
#                 merge job: how to render again a part whose task failed
#   --local       run the tasks as local processes instead (no Slurm), then merge
#   sbatch options (e.g. --partition=p --time=1:00:00 --cpus-per-task=8) are given to both
#   jobs; a task renders with --cpus-per-task threads. Options after -- go to nori
#   (e.g. -- -D size=1024 --aovs albedo,normal).
#
# A task writes a checkpoint every 10 minutes (nori --checkpoint; give another interval
# after --); a preempted or requeued task resumes from it (sbatch --requeue).
#
# Prints the array job's and the merge job's ids. A task that fails leaves the merge job
# never runnable, and Slurm cancels it (--kill-on-invalid-dep=yes); resubmit the task
# with --tasks K, which submits a new merge job.
set -euo pipefail

# The comment above: on stdout with status 0 when asked for (--help), on stderr with 2
# after a mistake.
usage() {
    if [ "${1:-}" = asked ]; then
        sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
        exit 0
    fi
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
}

here=$(cd "$(dirname "$0")" && pwd)
scene="" parts="" spp="" out="" nori="" tasks="" local=0
sbatch_options=() nori_options=()
while (($# > 0)); do
    case $1 in
    --parts) parts=${2:?--parts needs a number}; shift 2 ;;
    --spp) spp=${2:?--spp needs a number}; shift 2 ;;
    --out) out=${2:?--out needs a path}; shift 2 ;;
    --nori) nori=${2:?--nori needs a path}; shift 2 ;;
    --tasks) tasks=${2:?--tasks needs a list}; shift 2 ;;
    --local) local=1; shift ;;
    -h | --help) usage asked ;;
    --) shift; nori_options=("$@"); break ;;
    -*) sbatch_options+=("$1"); shift ;;
    *)
        if [ -n "$scene" ]; then
            echo "render.sh: more than one scene ('$scene' and '$1'); sbatch options take the" \
                "--name=value form" >&2
            exit 2
        fi
        scene=$1; shift ;;
    esac
done
[ -n "$scene" ] || { echo "render.sh: no scene file given" >&2; usage; }
[ -f "$scene" ] || { echo "render.sh: no such scene file: $scene" >&2; exit 2; }
[[ $parts =~ ^[1-9][0-9]*$ ]] || { echo "render.sh: --parts N (a positive number) is required" >&2; exit 2; }
if [ -n "$spp" ]; then
    [[ $spp =~ ^[1-9][0-9]*$ ]] || { echo "render.sh: --spp must be a positive number, got '$spp'" >&2; exit 2; }
    nori_options=(--spp "$spp" "${nori_options[@]}")
fi
nori=${nori:-$here/../../build/nori}
[ -x "$nori" ] || { echo "render.sh: nori program not found at $nori (give --nori PATH)" >&2; exit 2; }

# Absolute paths: the jobs may start in another folder, on another node.
absolute() { (cd "$(dirname "$1")" && echo "$(pwd)/$(basename "$1")"); }
scene=$(absolute "$scene")
nori=$(absolute "$nori")
out=${out:-${scene%.xml}}
mkdir -p "$(dirname "$out")"
out=$(absolute "$out")
outdir=${out}_parts
tasks=${tasks:-1-$parts}

# The part numbers of a Slurm array list ("1-4", "2,5", "1-7:2"), for cleaning and --local.
expand_tasks() {
    local item first last step k
    for item in ${1//,/ }; do
        step=1
        if [[ $item == *:* ]]; then step=${item#*:}; item=${item%%:*}; fi
        first=${item%-*} last=${item#*-}
        for ((k = first; k <= last; k += step)); do echo "$k"; done
    done
}
if ! [[ $tasks =~ ^[0-9]+(-[0-9]+(:[1-9][0-9]*)?)?(,[0-9]+(-[0-9]+(:[1-9][0-9]*)?)?)*$ ]]; then
    echo "render.sh: --tasks takes a Slurm array list (3, 2,5 or 1-7:2), got '$tasks'" >&2
    exit 2
fi
task_list=$(expand_tasks "$tasks")
for k in $task_list; do
    if ((k < 1 || k > parts)); then
        echo "render.sh: task $k is not a part of 1..$parts" >&2
        exit 2
    fi
done
mkdir -p "$outdir"
for k in $task_list; do
    rm -f "$outdir/part-$k.exr" "$outdir/part-$k.png" # no stale part of an earlier run
done

if ((local)); then
    # As many processes at once as cores, the cores shared among them.
    cores=$(nproc)
    count=$(echo "$task_list" | wc -w)
    concurrent=$((count < cores ? count : cores))
    export NORI_THREADS=$((cores / concurrent))
    failed=()
    running=0
    declare -A pids
    for k in $task_list; do
        if ((running == concurrent)); then
            wait -n || true
            running=$((running - 1))
        fi
        SLURM_ARRAY_TASK_ID=$k bash "$here/part.sh" "$nori" "$scene" "$parts" "$outdir" \
            "${nori_options[@]}" >"$outdir/part-$k.log" 2>&1 &
        pids[$k]=$!
        running=$((running + 1))
    done
    for k in $task_list; do
        wait "${pids[$k]}" || failed+=("$k")
    done
    if ((${#failed[@]} > 0)); then
        echo "render.sh: part(s) ${failed[*]} failed; see $outdir/part-K.log, then run again" \
            "with --tasks $(IFS=,; echo "${failed[*]}")" >&2
        exit 1
    fi
    bash "$here/merge.sh" "$nori" "$parts" "$outdir" "$out"
    exit
fi

command -v sbatch >/dev/null || { echo "render.sh: sbatch not found (Slurm's client); --local renders without Slurm" >&2; exit 2; }
name=nori-$(basename "${scene%.xml}")
# --requeue: a preempted task (or one of a failed node) goes back to the queue, and resumes
# from its checkpoint (part.sh).
array=$(sbatch --parsable --requeue --job-name="$name" --array="$tasks" --open-mode=append \
    --output="$outdir/part-%a.log" \
    "${sbatch_options[@]}" "$here/part.sh" "$nori" "$scene" "$parts" "$outdir" \
    "${nori_options[@]}")
array=${array%%;*} # "id;cluster" on multi-cluster sites
merge=$(sbatch --parsable --job-name="$name-merge" --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes --output="$outdir/merge.log" "${sbatch_options[@]}" \
    "$here/merge.sh" "$nori" "$parts" "$outdir" "$out")
merge=${merge%%;*}
echo "array job $array (parts $tasks of $parts) and merge job $merge submitted"
echo "parts and logs: $outdir/; result: $out.exr and $out.png"
echo "array-job $array"
echo "merge-job $merge"
