#!/usr/bin/env bash
# nori against Blender's Cycles on the diffuse Cornell box (scenes/cbox/cbox.xml with
# -D sphere=diffuse; scripts/cycles_cornell.py builds the same box in Blender), both on
# THREADS threads with a box filter, no denoising, no clamping, SPP samples per pixel.
# For each configuration: the render time (median and range over ROUNDS seeds), the MSE
# against the renderer's own converged render (REFERENCE_SPP, mean ± standard error), and
# the Monte Carlo efficiency 1/(time × MSE) relative to Cycles'. nori's configurations
# add one change at a time to Nori 2's way (independent sampler, light sampled by area,
# lights chosen by power), so that each change's share shows; the last is the default.
# Last, the two references against each other (the same box: their means per channel and
# the MSE between them, which holds what differs between the two scenes, e.g. the
# spheres' facets).
#   scripts/bench_cycles.sh [BUILD_DIR] [SPP] [REFERENCE_SPP] [ROUNDS] [SIZE] [THREADS]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
spp="${2:-64}"
reference_spp="${3:-2048}"
rounds="${4:-3}"
size="${5:-512}"
threads="${6:-2}"
blender="${BLENDER:-blender}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

nori() { # output name, then -D definitions; prints the render time in seconds
    local name="$1"; shift
    "$build/nori" --no-progress --threads "$threads" -D integrator=path_mis -D size="$size" -D sphere=diffuse \
        -D filter=box "$@" "$here/scenes/cbox/cbox.xml" -o "$out/$name.exr" 2>&1 |
        awk -f "$here/scripts/done_seconds.awk"
}
cycles() { # output name, samples, seed; prints the render time in seconds
    "$blender" -b --factory-startup --python "$here/scripts/cycles_cornell.py" -- \
        "$here/scenes/cbox/meshes" "$out/$1.exr" "$2" "$3" "$threads" "$size" 2>&1 |
        sed -nE 's/^render seconds: ([0-9.]+)/\1/p'
}
mse() { # image, reference; prints the MSE
    "$build/nori-imgtool" diff "$1" "$2" | awk '$1 == "rmse" { print $2 * $2 }'
}
# summarize "TIMES" "ERRORS" [BASELINE]: scripts/bench_summary.awk's line.
summarize() {
    echo "$1 | $2" | awk -v baseline="${3:-}" -f "$here/scripts/bench_summary.awk"
}

echo "== Diffuse Cornell box, ${size}x$size, $spp spp, $threads threads, $rounds rounds;" \
     "references $reference_spp spp"
echo "references: Cycles $(cycles cycles-reference "$reference_spp" 9999) s," \
     "nori $(nori nori-reference -D sampler=sobol -D spp="$reference_spp" -D seed=9999) s"
printf '%-40s %22s %24s %10s %9s\n' "renderer, configuration" "time (s) median, range" \
    "MSE mean ± s.e." "efficiency" "to Cycles"

times="" errors=""
for round in $(seq 1 "$rounds"); do
    times+="$(cycles run "$spp" "$round") "
    errors+="$(mse "$out/run.exr" "$out/cycles-reference.exr") "
done
line="$(summarize "$times" "$errors")"
cycles_efficiency="${line##* }"
printf '%-40s %s\n' "Cycles $("$blender" -v 2>/dev/null | sed -n "1s/Blender //p"), 64 bounces" \
    "${line% *}"

configurations=(
    "independent, area, power|-D sampler=independent -D lightsampling=area -D lightsampler=power"
    "+ sobol|-D sampler=sobol -D lightsampling=area -D lightsampler=power"
    "+ solid angle|-D sampler=sobol -D lightsampling=solidangle -D lightsampler=power"
    "+ light tree (the defaults)|-D sampler=sobol -D lightsampling=solidangle -D lightsampler=bvh"
)
for configuration in "${configurations[@]}"; do
    label="${configuration%%|*}"
    read -r -a definitions <<< "${configuration#*|}"
    times="" errors=""
    for round in $(seq 1 "$rounds"); do
        times+="$(nori run "${definitions[@]}" -D spp="$spp" -D seed="$round") "
        errors+="$(mse "$out/run.exr" "$out/nori-reference.exr") "
    done
    line="$(summarize "$times" "$errors" "$cycles_efficiency")"
    printf '%-40s %s\n' "nori, $label" "${line% *}"
done

echo
echo "The references against each other (nori's against Cycles'):"
"$build/nori-imgtool" diff "$out/nori-reference.exr" "$out/cycles-reference.exr"
for image in nori-reference cycles-reference; do
    echo "$image mean: $("$build/nori-imgtool" info "$out/$image.exr" |
        sed -n 's/^mean //p')"
done
