#!/usr/bin/env bash
# Equal-time comparison of path_mis, photonmapper and progressivephotonmapper on the
# photon-mapping example (scenes/caustics/caustics.xml): each renders for the same time,
# then its RMSE against a converged path_mis reference is measured over the image and in
# the caustic under the glass sphere. The reference is rendered once and kept.
#   scripts/bench_photons.sh [--seconds T] [--reference-spp N] [--build DIR] [--out DIR]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail

seconds=30
reference_spp=16384
build=build
out=build/bench-photons
while [[ $# -gt 0 ]]; do
    case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --reference-spp) reference_spp=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "bench_photons.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
done

scene=scenes/caustics/caustics.xml
# The caustic of the glass sphere on the floor, in pixels of the 256 × 256 image.
caustic=150,200,80,50
nori=$build/nori
imgtool=$build/nori-imgtool
mkdir -p "$out"

if [[ ! -f $out/reference_${reference_spp}spp.exr ]]; then
    echo "Rendering the reference: path_mis at $reference_spp spp (once)"
    "$nori" --no-progress -D integrator=path_mis -D spp="$reference_spp" \
        -o "$out/reference_${reference_spp}spp" "$scene" 2>&1 | grep '^Done'
fi
reference=$out/reference_${reference_spp}spp.exr

rmse() { "$imgtool" diff "$@" | awk '$1 == "rmse" { print $2 }'; }

printf '%-24s %8s %10s %12s %14s\n' integrator seconds spp "rmse(image)" "rmse(caustic)"
for integrator in path_mis photonmapper progressivephotonmapper; do
    log=$("$nori" --no-progress --time "$seconds" -D integrator=$integrator -D spp=1000000 \
        -o "$out/$integrator" "$scene" 2>&1)
    done_line=$(grep '^Done in' <<<"$log")
    spp=$(sed -E 's/.*\(([0-9]+) spp.*/\1/' <<<"$done_line")
    time=$(sed -E 's/^Done in ([^ ]+ [a-z]+).*/\1/' <<<"$done_line")
    printf '%-24s %8s %10s %12.5f %14.5f\n' $integrator "$time" "$spp" \
        "$(rmse "$out/$integrator.exr" "$reference")" \
        "$(rmse --crop $caustic "$out/$integrator.exr" "$reference")"
done
