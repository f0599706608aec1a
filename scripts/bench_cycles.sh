#!/usr/bin/env bash
# nori against Blender's Cycles on two boxes, each built the same in both renderers:
#   cbox     the diffuse Cornell box (scenes/cbox/cbox.xml with -D sphere=diffuse, analytic
#            spheres; scripts/cycles_cornell.py builds it in Blender);
#   meshbox  the mesh-sphere box (scenes/meshbox/meshbox.xml: two 5,120-triangle spheres
#            with vertex normals; scripts/cycles_meshbox.py), whose errors leave out the
#            light and its 2-pixel rim (nori-imgtool diff --exclude-above 1.5
#            --exclude-rim 2).
# Both renderers on THREADS threads with a box filter, no denoising, no clamping, SPP
# samples per pixel. For each configuration: the render time (median and range over
# ROUNDS seeds), the MSE against the renderer's own converged render (REFERENCE_SPP, mean ±
# standard error), and the Monte Carlo efficiency 1/(time × MSE) relative to Cycles'.
# nori's configurations add one change at a time to Nori 2's way (independent sampler,
# light sampled by area, lights chosen by power) up to the defaults; on the mesh box
# also the defaults without MIS (light sampling only, path_ems). Last, the two
# references against each other (their means per channel and the MSE between them: what
# differs between the two renderers' answers, which a render's MSE against the other's
# reference adds to its own).
#   scripts/bench_cycles.sh [BUILD_DIR] [SPP] [REFERENCE_SPP] [ROUNDS] [SIZE] [THREADS]
# Environment: BOXES (default "cbox meshbox"), BLENDER (default blender), REFERENCES=DIR
# keeps the references in DIR and reuses those already there (they take most of the time).
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
boxes="${BOXES:-cbox meshbox}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
references="${REFERENCES:-$out}"
mkdir -p "$references"

# The box being measured: its scene, nori's definitions, Cycles' script and first
# argument, and what the errors leave out.
set_box() {
    case "$1" in
        cbox)
            scene="$here/scenes/cbox/cbox.xml"
            box_defines=(-D integrator=path_mis -D sphere=diffuse -D filter=box)
            cycles_script="$here/scripts/cycles_cornell.py"
            cycles_input="$here/scenes/cbox/meshes"
            diff_options=()
            title="Diffuse Cornell box" ;;
        meshbox)
            scene="$here/scenes/meshbox/meshbox.xml"
            box_defines=(-D integrator=path_mis)
            cycles_script="$here/scripts/cycles_meshbox.py"
            cycles_input="$here/scenes/meshbox"
            diff_options=(--exclude-above 1.5 --exclude-rim 2)
            title="Mesh-sphere box (light and rim left out)" ;;
        *) echo "unknown box '$1' (cbox or meshbox)" >&2; exit 2 ;;
    esac
}

nori() { # output file, then -D definitions; prints the render time in seconds
    local file="$1"; shift
    "$build/nori" --no-progress --threads "$threads" -D size="$size" "${box_defines[@]}" "$@" \
        "$scene" -o "$file" 2>&1 | awk -f "$here/scripts/done_seconds.awk"
}
cycles() { # output file, samples, seed; prints the render time in seconds
    "$blender" -b --factory-startup --python "$cycles_script" -- \
        "$cycles_input" "$1" "$2" "$3" "$threads" "$size" 2>&1 |
        sed -nE 's/^render seconds: ([0-9.]+)/\1/p'
}
mse() { # image, reference; prints the MSE
    "$build/nori-imgtool" diff "${diff_options[@]}" "$1" "$2" |
        awk '$1 == "rmse" { print $2 * $2 }'
}
# summarize "TIMES" "ERRORS" [BASELINE]: scripts/bench_summary.awk's line.
summarize() {
    echo "$1 | $2" | awk -v baseline="${3:-}" -f "$here/scripts/bench_summary.awk"
}

for box in $boxes; do
    set_box "$box"
    cycles_reference="$references/$box-cycles-$reference_spp-$size.exr"
    nori_reference="$references/$box-nori-$reference_spp-$size.exr"
    echo "== $title, ${size}x$size, $spp spp, $threads threads, $rounds rounds;" \
         "references $reference_spp spp"
    [ -f "$cycles_reference" ] ||
        echo "reference: Cycles $(cycles "$cycles_reference" "$reference_spp" 9999) s"
    [ -f "$nori_reference" ] ||
        echo "reference: nori $(nori "$nori_reference" -D sampler=sobol -D spp="$reference_spp" \
            -D seed=9999) s"
    printf '%-46s %22s %24s %10s %9s\n' "renderer, configuration" "time (s) median, range" \
        "MSE mean ± s.e." "efficiency" "to Cycles"

    times="" errors=""
    for round in $(seq 1 "$rounds"); do
        times+="$(cycles "$out/run.exr" "$spp" "$round") "
        errors+="$(mse "$out/run.exr" "$cycles_reference") "
    done
    line="$(summarize "$times" "$errors")"
    cycles_efficiency="${line##* }"
    printf '%-46s %s\n' "Cycles $("$blender" -v 2>/dev/null | sed -n "1s/Blender //p"), 64 bounces" \
        "${line% *}"

    defaults="-D sampler=sobol -D lightsampling=solidangle -D lightsampler=bvh"
    configurations=(
        "independent, area, power|-D sampler=independent -D lightsampling=area -D lightsampler=power"
        "+ sobol|-D sampler=sobol -D lightsampling=area -D lightsampler=power"
        "+ solid angle|-D sampler=sobol -D lightsampling=solidangle -D lightsampler=power"
        "+ light tree (the defaults)|$defaults"
    )
    if [ "$box" = meshbox ]; then
        configurations+=(
            "defaults, light sampling only (path_ems)|$defaults -D integrator=path_ems"
        )
    fi
    for configuration in "${configurations[@]}"; do
        label="${configuration%%|*}"
        read -r -a definitions <<< "${configuration#*|}"
        times="" errors=""
        for round in $(seq 1 "$rounds"); do
            times+="$(nori "$out/run.exr" "${definitions[@]}" -D spp="$spp" -D seed="$round") "
            errors+="$(mse "$out/run.exr" "$nori_reference") "
        done
        line="$(summarize "$times" "$errors" "$cycles_efficiency")"
        printf '%-46s %s\n' "nori, $label" "${line% *}"
    done

    echo
    echo "The references against each other (nori's against Cycles'):"
    "$build/nori-imgtool" diff "${diff_options[@]}" "$nori_reference" "$cycles_reference"
    for image in "$nori_reference" "$cycles_reference"; do
        echo "$(basename "$image" .exr) mean: $("$build/nori-imgtool" info "$image" |
            sed -n 's/^mean //p')"
    done
    echo
done
