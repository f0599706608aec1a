#!/usr/bin/env bash
# Equal-time error of path_mis, bdpt, lighttracer and progressivephotonmapper (issue 44's
# figures): each renders for SECONDS on all cores (as many samples as fit), ROUNDS times
# with different seeds, and its relMSE (nori-imgtool diff: Σ(a−b)²/(b²+0.01) per channel,
# averaged) against a converged bdpt reference is printed for the whole image and a
# caustic region, as the mean and the range over the rounds, with the samples per pixel
# each reached:
# - the default Cornell box (scenes/cbox/cbox.xml, 512×512; caustic: the floor in front
#   of the glass sphere, lit through it), the README's first image;
# - Veach's plates (scenes/veach/veach.xml, 640×384, full global illumination; no caustic:
#   the region is the plates);
# - the environment map scene (scenes/envmap/envmap.xml, 480×270; caustic: the glass
#   sphere's on the floor).
# The reference (bdpt, REFERENCE_SPP, seed 99) adds its own noise to every figure, about
# (bdpt's spp)/REFERENCE_SPP of bdpt's relMSE. REFERENCES, if given, is a folder where
# references are kept and reused between runs (they take minutes); SCENES picks some of
# cbox, veach and envmap (all by default).
#   scripts/bench_bdpt.sh [BUILD_DIR] [SECONDS] [ROUNDS] [REFERENCE_SPP] [REFERENCES] [SCENES]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
seconds="${2:-10}"
rounds="${3:-2}"
reference_spp="${4:-512}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
references="${5:-$out}"
scenes="${6:-cbox veach envmap}"
mkdir -p "$references"

relmse() { # image, reference[, crop]
    "$build/nori-imgtool" diff "$1" "$2" ${3:+--crop "$3"} | awk '$1 == "relmse" { print $2 }'
}

# bench TITLE SCENE CROP [-D definitions], if SCENES names the scene
bench() {
    local title="$1" scene="$2" crop="$3"; shift 3
    [[ " $scenes " == *" $(basename "$scene" .xml) "* ]] || return 0
    local reference="$references/$(basename "$scene" .xml)-bdpt$reference_spp.exr"
    if [ ! -f "$reference" ]; then
        "$build/nori" --no-progress -D integrator=bdpt -D seed=99 --spp "$reference_spp" "$@" \
            "$scene" -o "$reference" > /dev/null
    fi
    echo "== $title: $scene, ${seconds} s a render, $rounds rounds; reference bdpt $reference_spp spp"
    printf '%-26s %8s %26s %26s\n' integrator spp "relMSE image: mean [range]" \
        "relMSE $crop: mean [range]"
    for integrator in path_mis bdpt lighttracer progressivephotonmapper; do
        local spps="" whole="" region=""
        for round in $(seq 1 "$rounds"); do
            local spp
            spp=$("$build/nori" --no-progress --time "$seconds" --spp 1000000 -D integrator=$integrator \
                -D seed="$round" "$@" "$scene" -o "$out/run.exr" 2>&1 |
                sed -nE 's/^Done in .*\(([0-9]+) spp.*/\1/p')
            spps+="$spp "
            whole+="$(relmse "$out/run.exr" "$reference") "
            region+="$(relmse "$out/run.exr" "$reference" "$crop") "
        done
        echo "$integrator|$spps|$whole|$region" | awk -F'|' '
            function summary(list,    n, v, i, sum, lo, hi) {
                n = split(list, v, " "); sum = 0; lo = v[1]; hi = v[1]
                for (i = 1; i <= n; ++i) { sum += v[i]; if (v[i] < lo) lo = v[i]; if (v[i] > hi) hi = v[i] }
                return sprintf("%.4g [%.4g, %.4g]", sum / n, lo, hi)
            }
            { printf "%-26s %8s %26s %26s\n", $1, $2, summary($3), summary($4) }'
    done
}

bench "Cornell box (default)" "$here/scenes/cbox/cbox.xml" 330,462,80,16
bench "Veach plates" "$here/scenes/veach/veach.xml" 40,220,570,160
bench "Environment map, glass" "$here/scenes/envmap/envmap.xml" 280,190,100,35
