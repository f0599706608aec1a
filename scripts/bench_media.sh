#!/usr/bin/env bash
# The figures of participating media on scenes/media/cloud.xml (shadow rays through the
# cloud dominate): render time and RMSE against a converged reference for delta tracking,
# ratio tracking and ray marching at equal samples per pixel, and the render time with
# the majorant grid against one global majorant (ratio and delta tracking, two densities).
#   scripts/bench_media.sh [BUILD_DIR] [SPP] [REFERENCE_SPP]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
spp="${2:-64}"
reference_spp="${3:-2048}"
size=128
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
scene="$here/scenes/media/cloud.xml"

render() { # name, then -D definitions; prints the render time in seconds
    local name="$1"; shift
    "$build/nori" -D size=$size "$@" "$scene" -o "$out/$name.exr" 2>&1 |
        awk -f "$here/scripts/done_seconds.awk"
}
rmse() { "$build/nori-imgtool" diff "$1" "$out/reference.exr" | awk '/^rmse/ { print $2 }'; }

echo "reference: ratio tracking, $reference_spp spp, ${size}x$size ..."
render reference -D spp="$reference_spp" -D seed=99 > /dev/null
printf '%-28s %10s %12s\n' "estimator ($spp spp)" "time (s)" "RMSE"
for estimator in delta ratio raymarch; do
    seconds=$(render "$estimator" -D spp="$spp" -D transmittance=$estimator -D step=0.01)
    printf '%-28s %10s %12s\n' "$estimator" "$seconds" "$(rmse "$out/$estimator.exr")"
done
seconds=$(render raymarch-coarse -D spp="$spp" -D transmittance=raymarch -D step=0.05)
printf '%-28s %10s %12s\n' "raymarch (step 0.05)" "$seconds" "$(rmse "$out/raymarch-coarse.exr")"
echo
printf '%-36s %10s %10s\n' "majorant grid ($spp spp)" "16^3 (s)" "1^3 (s)"
for density in 12 48; do
    for estimator in ratio delta; do
        fine=$(render "fine" -D spp="$spp" -D transmittance=$estimator -D density=$density)
        global=$(render "global" -D spp="$spp" -D transmittance=$estimator -D density=$density \
            -D majorants=1)
        printf '%-36s %10s %10s\n' "$estimator tracking, density scale $density" "$fine" "$global"
    done
done
