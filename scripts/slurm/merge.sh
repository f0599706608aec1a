#!/usr/bin/env bash
# The last step of a split render: merges the parts OUTDIR/part-1..N.exr into OUT.exr and
# OUT.png. Parts that are not there are left off the list, so that `nori merge` names
# them; it refuses to merge then, unless --allow-missing is among the options.
#   merge.sh NORI N OUTDIR OUT [nori merge options...]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
nori=$1 parts=$2 outdir=$3 out=$4
shift 4
files=()
for ((k = 1; k <= parts; ++k)); do
    if [ -f "$outdir/part-$k.exr" ]; then
        files+=("$outdir/part-$k.exr")
    fi
done
if ((${#files[@]} == 0)); then
    echo "merge.sh: none of the $parts parts is in $outdir" >&2
    exit 1
fi
exec "$nori" merge "${files[@]}" -o "$out" "$@"
