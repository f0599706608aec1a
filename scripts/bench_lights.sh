#!/usr/bin/env bash
# Light sampling's figures, each configuration's render time, its error against a
# converged reference and the Monte Carlo efficiency 1/(time × error), relative to the
# first configuration of its scene:
# - the Cornell box (its one quad light; the glass sphere made diffuse) and the window
#   room (scenes/window, a large window quad seen at grazing angles): each sampler
#   (independent, sobol) with the light sampled by area (Nori 2's way) or in solid angle;
#   error: MSE;
# - the many-light scene (scripts/make_many_lights.py: 1000 small lights over a floor):
#   each sampler with the lights chosen by power or by the light tree (bvh); error: relMSE
#   (the issue's measure: the lights' radiances span two decades);
# - the Cornell box, Veach's plates, the envmap scene and the meadow at SPP: the time with
#   the light tree against power selection, alternating, for the slowdown the tree costs.
# Each configuration renders ROUNDS times with different seeds: the time is their median
# (and range), the error their mean ± its standard error. The reference (sobol, the last
# light option, REFERENCE_SPP) adds its own error, about SPP/REFERENCE_SPP of an
# independent render's.
#   scripts/bench_lights.sh [BUILD_DIR] [SPP] [REFERENCE_SPP] [ROUNDS] [SIZE]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
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
    "$build/nori" --no-progress -D integrator=path_mis -D size="$size" "$@" "$scene" -o "$out/$name.exr" 2>&1 |
        awk -f "$here/scripts/done_seconds.awk"
}
error() { # image; prints its MSE or relMSE (by $metric) against the reference
    "$build/nori-imgtool" diff "$1" "$out/reference.exr" |
        awk -v metric="$metric" '($1 == "rmse" && metric == "mse") { print $2 * $2 }
                                 ($1 == "relmse" && metric == "relmse") { print $2 }'
}

# bench_scene TITLE SCENE VARIABLE "VALUES" [-D definitions shared by every render]:
# every sampler with the scene's variable VARIABLE set to each of VALUES in turn.
bench_scene() {
    local title="$1" scene="$2" variable="$3" values="$4"; shift 4
    echo "== $title: $scene, ${size}x$size, $spp spp, $rounds rounds; reference $reference_spp spp"
    render "$scene" reference "$@" -D sampler=sobol -D "$variable=${values##* }" \
        -D spp="$reference_spp" -D seed=9999 > /dev/null
    printf '%-24s %22s %24s %12s %9s\n' "sampler, $variable" "time (s) median, range" \
        "$metric mean ± s.e." "efficiency" "relative"
    local baseline=""
    for sampler in independent sobol; do
        for value in $values; do
            local times="" errors=""
            for round in $(seq 1 "$rounds"); do
                times+="$(render "$scene" run "$@" -D sampler=$sampler \
                    -D "$variable=$value" -D spp="$spp" -D seed="$round") "
                errors+="$(error "$out/run.exr") "
            done
            local line
            line=$(echo "$times" "|" "$errors" |
                awk -v baseline="$baseline" -f "$here/scripts/bench_summary.awk")
            [ -z "$baseline" ] && baseline="${line##* }"
            printf '%-24s %s\n' "$sampler, $value" "${line% *}"
        done
    done
    echo
}

# time_scene TITLE SCENE: the scene rendered with the light tree and with power
# selection, alternately, ROUNDS times each; the median times and their ratio.
time_scene() {
    local title="$1" scene="$2" tree="" power=""
    for round in $(seq 1 "$rounds"); do
        power+="$(render "$scene" run -D spp="$spp" -D seed="$round" -D lightsampler=power) "
        tree+="$(render "$scene" run -D spp="$spp" -D seed="$round" -D lightsampler=bvh) "
    done
    echo "$power" "|" "$tree" | awk -v title="$title" '
        function median(a, n,    i, j, x) {
            for (i = 2; i <= n; ++i)
                for (j = i; j > 1 && a[j - 1] > a[j]; --j) { x = a[j]; a[j] = a[j - 1]; a[j - 1] = x }
            return (n % 2) ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
        }
        {
            n = 0; m = 0
            for (i = 1; $i != "|"; ++i) p[++n] = $i
            for (i = i + 1; i <= NF; ++i) t[++m] = $i
            mp = median(p, n); mt = median(t, m)
            printf "%-16s %8.2f (%5.2f-%-5.2f) %8.2f (%5.2f-%-5.2f) %+7.1f %%\n", title, mp, p[1],
                p[n], mt, t[1], t[m], 100 * (mt / mp - 1)
        }'
}

metric=mse
bench_scene "Cornell box" "$here/scenes/cbox/cbox.xml" lightsampling "area solidangle" \
    -D sphere=diffuse
bench_scene "Window room" "$here/scenes/window/window.xml" lightsampling "area solidangle"

metric=relmse
python3 "$here/scripts/make_many_lights.py" "$out/manylights" 1000 1
bench_scene "Many lights" "$out/manylights/manylights.xml" lightsampler "power bvh"

echo "== Light tree against power selection, $spp spp (the Cornell box at ${size}x$size, the others"
echo "   at their own sizes), $rounds rounds each, alternating"
printf '%-16s %22s %22s %8s\n' "scene" "power: median (range)" "bvh: median (range)" "change"
time_scene "Cornell box" "$here/scenes/cbox/cbox.xml"
time_scene "Veach" "$here/scenes/veach/veach.xml"
time_scene "Envmap" "$here/scenes/envmap/envmap.xml"
time_scene "Meadow" "$here/scenes/meadow/meadow.xml"
