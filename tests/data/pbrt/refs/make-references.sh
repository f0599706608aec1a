#!/bin/bash
# Renders the pbrt-v4 references of the grey test scenes: each scene with seeds 1 to 8 at
# 256 samples per pixel, into refs/<scene>-seed<K>.exr. Made once with the pbrt-v4 build of
# ../shared/tools (commit 5f7a606806a4ac7b939131ded9d7a30ebd02416e) and committed: the
# tests do not need pbrt-v4.
#   usage: tests/data/pbrt/refs/make-references.sh PBRT [SCENE.pbrt...]
set -euo pipefail
if [[ "${1:-}" == "-h" || "${1:-}" == "--help" || $# -lt 1 ]]; then
    echo "usage: $0 PBRT [SCENE.pbrt...]   (renders the given scenes of tests/data/pbrt, or"
    echo "       all of them, with seeds 1..8 at 256 spp)"
    [[ $# -ge 1 ]] && exit 0 || exit 2
fi
pbrt=$(realpath "$1")
shift
cd "$(dirname "$0")/.."
scenes=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=(*.pbrt)
for scene in "${scenes[@]}"; do
    for seed in 1 2 3 4 5 6 7 8; do
        "$pbrt" --quiet --nthreads 2 --spp 256 --seed "$seed" \
            --outfile "refs/${scene%.pbrt}-seed$seed.exr" "$scene"
    done
done
