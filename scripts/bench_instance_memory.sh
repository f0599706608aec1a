#!/usr/bin/env bash
# The peak memory of a scene of many instances, XML included: one shape group (a mesh of
# about 5,000 triangles from `nori-bench --make-mesh`) placed N times by <mesh
# type="instance"> elements, each with a <rotate> and a <translate> (about 160 bytes of
# XML), rendered at 32×32, 1 spp with the normals integrator. Prints the peak resident
# set (/usr/bin/time's %M) of `nori` for each N over ROUNDS runs (median and range) and
# the bytes per instance: the difference of the medians over the difference of the N.
#   scripts/bench_instance_memory.sh [BUILD_DIR] [SMALL_N] [LARGE_N] [ROUNDS]
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
small="${2:-20000}"
large="${3:-200000}"
rounds="${4:-3}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

"$build/nori-bench" --make-mesh 5000 "$out/mesh.obj" > /dev/null

scene() { # N: writes $out/instancesN.xml
    awk -v n="$1" 'BEGIN {
        srand(7);
        print "<scene>";
        print "<integrator type=\"normals\"/>";
        print "<sampler type=\"independent\"><integer name=\"sampleCount\" value=\"1\"/></sampler>";
        print "<camera type=\"perspective\"><transform name=\"toWorld\"><lookat origin=\"0,0,400\" target=\"0,0,0\" up=\"0,1,0\"/></transform><float name=\"fov\" value=\"60\"/><integer name=\"width\" value=\"32\"/><integer name=\"height\" value=\"32\"/></camera>";
        print "<mesh type=\"shapegroup\" id=\"g\"><mesh type=\"obj\"><string name=\"filename\" value=\"mesh.obj\"/></mesh></mesh>";
        for (i = 0; i < n; ++i)
            printf "<mesh type=\"instance\"><ref id=\"g\"/><transform name=\"toWorld\"><rotate axis=\"0,1,0\" angle=\"%.2f\"/><translate value=\"%.3f, %.3f, %.3f\"/></transform></mesh>\n",
                360 * rand(), 400 * rand() - 200, 400 * rand() - 200, 400 * rand() - 200;
        print "</scene>";
    }' > "$out/instances$1.xml"
}

peak() { # N: prints the median and range of the peak RSS in KB over the rounds
    local kb=()
    for ((round = 0; round < rounds; ++round)); do
        kb+=("$(/usr/bin/time -f %M "$build/nori" --no-progress -o "$out/render" \
            "$out/instances$1.xml" 2>&1 > /dev/null | tail -n 1)")
    done
    printf '%s\n' "${kb[@]}" | sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)], v[1], v[NR] }'
}

scene "$small"
scene "$large"
read -r small_kb small_min small_max <<< "$(peak "$small")"
read -r large_kb large_min large_max <<< "$(peak "$large")"
echo "instances  peak RSS (KB, median of $rounds)  range"
printf '%9d  %28d  %d-%d\n' "$small" "$small_kb" "$small_min" "$small_max"
printf '%9d  %28d  %d-%d\n' "$large" "$large_kb" "$large_min" "$large_max"
awk -v a="$small_kb" -v b="$large_kb" -v n="$small" -v m="$large" \
    'BEGIN { printf "bytes per instance: %.0f\n", (b - a) * 1024 / (m - n) }'
