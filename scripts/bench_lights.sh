#!/usr/bin/env bash
# Light sampling's figures: for the Cornell box (its one quad light; the glass sphere made
# diffuse) and the window room (scenes/window, a large window quad seen at grazing angles),
# the render time, the MSE against a converged reference and the Monte Carlo efficiency
# 1/(time × MSE) of each sampler (independent, sobol) with the light sampled by area or in
# solid angle, each relative to independent with area sampling (Nori 2's way). Each
# configuration renders ROUNDS times with different seeds: the time is their median (and
# range), the MSE their mean ± its standard error. The reference (sobol, solid angle,
# REFERENCE_SPP) adds its own MSE, about SPP/REFERENCE_SPP of an independent render's.
#   scripts/bench_lights.sh [BUILD_DIR] [SPP] [REFERENCE_SPP] [ROUNDS] [SIZE]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
spp="${2:-64}"
reference_spp="${3:-2048}"
rounds="${4:-3}"
size="${5:-512}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

render() { # scene, output name, then -D definitions; prints the render time in seconds
    local scene="$1" name="$2"; shift 2
    "$build/nori" --no-progress -D size="$size" "$@" "$scene" -o "$out/$name.exr" 2>&1 |
        sed -nE 's/^Done in ([0-9.]+) (m?s).*/\1 \2/p' |
        awk '{ print ($2 == "ms") ? $1 / 1000 : $1 }'
}
mse() { "$build/nori-imgtool" diff "$1" "$out/reference.exr" | awk '/^rmse/ { print $2 * $2 }'; }

bench_scene() { # title, scene, then -D definitions shared by every render
    local title="$1" scene="$2"; shift 2
    echo "== $title: $scene, ${size}x$size, $spp spp, $rounds rounds; reference $reference_spp spp"
    render "$scene" reference "$@" -D sampler=sobol -D lightsampling=solidangle \
        -D spp="$reference_spp" -D seed=9999 > /dev/null
    printf '%-24s %22s %24s %12s %9s\n' "sampler, light" "time (s) median, range" \
        "MSE mean ± s.e." "efficiency" "relative"
    local baseline=""
    for sampler in independent sobol; do
        for lightsampling in area solidangle; do
            local times="" errors=""
            for round in $(seq 1 "$rounds"); do
                times+="$(render "$scene" run "$@" -D sampler=$sampler \
                    -D lightsampling=$lightsampling -D spp="$spp" -D seed="$round") "
                errors+="$(mse "$out/run.exr") "
            done
            local line
            line=$(echo "$times" "|" "$errors" | awk -v baseline="$baseline" '
                {
                    n = 0; m = 0
                    for (i = 1; $i != "|"; ++i) t[++n] = $i
                    for (i = i + 1; i <= NF; ++i) e[++m] = $i
                    for (i = 2; i <= n; ++i) # insertion sort (POSIX awk has no asort)
                        for (j = i; j > 1 && t[j - 1] > t[j]; --j) { x = t[j]; t[j] = t[j - 1]; t[j - 1] = x }
                    median = (n % 2) ? t[(n + 1) / 2] : (t[n / 2] + t[n / 2 + 1]) / 2
                    mean = 0; for (i = 1; i <= m; ++i) mean += e[i]; mean /= m
                    var = 0; for (i = 1; i <= m; ++i) var += (e[i] - mean) ^ 2
                    se = (m > 1) ? sqrt(var / (m - 1) / m) : 0
                    efficiency = 1 / (median * mean)
                    relative = (baseline == "") ? 1 : efficiency / baseline
                    printf "%10.2f %5.2f-%-5.2f %12.4e ± %8.2e %12.4g %8.2fx %s\n", median, t[1],
                        t[n], mean, se, efficiency, relative, efficiency
                }')
            [ -z "$baseline" ] && baseline="${line##* }"
            printf '%-24s %s\n' "$sampler, $lightsampling" "${line% *}"
        done
    done
    echo
}

bench_scene "Cornell box" "$here/scenes/cbox/cbox.xml" -D sphere=diffuse
bench_scene "Window room" "$here/scenes/window/window.xml"
