#!/usr/bin/env bash
# Renders the example scenes with two builds of nori and reports whether each pair of
# images is the same bit for bit: the check of a refactoring that must not change images.
#   scripts/compare_renders.sh OLD_NORI NEW_NORI [SPP]
# The Cornell box is also rendered with every surface integrator.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
old=$1 new=$2 spp=${3:-4}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

scenes=()
for scene in cbox/cbox veach/veach envmap/envmap textured/textured caustics/caustics \
             disney/sweep media/media media/cloud realistic/realistic spheres/spheres \
             meadow/meadow; do
    scenes+=("$root/scenes/$scene.xml")
done
# cbox with each surface integrator, at a quarter of the size.
jobs=()
for scene in "${scenes[@]}"; do
    jobs+=("$(basename "$scene" .xml)|$scene|")
done
for integrator in path_mis path_ems path_mats direct direct_ems direct_mats direct_mis \
                  whitted volpath photonmapper progressivephotonmapper; do
    jobs+=("cbox-$integrator|$root/scenes/cbox/cbox.xml|-D integrator=$integrator -D size=128")
done

same=0 different=0
for job in "${jobs[@]}"; do
    IFS='|' read -r name scene defines <<<"$job"
    for build in old new; do
        binary=$old
        [ "$build" = new ] && binary=$new
        # shellcheck disable=SC2086 # the defines are words
        "$binary" --no-progress --spp "$spp" $defines -o "$work/$name-$build" "$scene" \
            >/dev/null 2>&1 ||
            echo "$name: $build build failed to render" >&2
    done
    if cmp -s "$work/$name-old.exr" "$work/$name-new.exr"; then
        echo "same       $name"
        same=$((same + 1))
    else
        echo "DIFFERENT  $name"
        different=$((different + 1))
    fi
done
echo "$same same, $different different"
[ "$different" -eq 0 ]
