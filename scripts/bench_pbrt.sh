#!/usr/bin/env bash
# pbrt-v4 and nori side by side on pbrt-v4 scene files: each scene is rendered by both
# from the same file, interleaved (pbrt-v4, nori, pbrt-v4, nori, ...), on 2 threads and on
# 1 thread pinned to one core, ROUNDS rounds of two seeds each. Per scene, thread count
# and renderer it prints, as the median and the range over the renders:
#   first pixel  the time before rendering starts (parsing, loading, BVH build): the wall
#                time less the render time (so it also holds writing the image)
#   render       the render time (pbrt-v4's progress bar, nori's "Done in")
#   peak RSS     the process's peak resident memory
#   variance     the per-pixel variance, MSE(seed 1, seed 2)/2 of each round: each renderer
#                against its own answer (pbrt-v4's spectral noise counts against it)
#   efficiency   the Monte Carlo efficiency 1/(render time × variance), and nori's ratio to
#                pbrt-v4's
#   scripts/bench_pbrt.sh PBRT [--rounds N] [--spp N] [--threads "2 1"] [--build DIR]
#                         SCENE.pbrt...
# PBRT is a pbrt-v4 program (a build is in ../shared/tools/). --spp overrides both scenes'
# sample counts (default: the scene's). Needs GNU time (/usr/bin/time, Debian's `time`)
# and taskset (util-linux). A renderer that fails on a scene is reported with its exit
# status and its last lines, and the benchmark goes on with the other.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
(($#)) || { echo "usage: bench_pbrt.sh PBRT [options] SCENE.pbrt... (see --help)" >&2; exit 2; }
pbrt="$(realpath "$1")"
shift
rounds=3 spp="" thread_counts="2 1" build="$here/build" scenes=()
while (($#)); do
    case "$1" in
    --rounds) rounds="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --threads) thread_counts="$2"; shift 2 ;;
    --build) build="$(realpath "$2")"; shift 2 ;;
    -*) echo "bench_pbrt.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) scenes+=("$(realpath "$1")"); shift ;;
    esac
done
((${#scenes[@]})) || { echo "bench_pbrt.sh: no scene given" >&2; exit 2; }
for tool in /usr/bin/time taskset; do
    command -v "$tool" > /dev/null ||
        { echo "bench_pbrt.sh: needs $tool (apt-get install time util-linux)" >&2; exit 2; }
done
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

# run RENDERER THREADS SEED SCENE: renders into $out/RENDERER-SEED.exr and appends
# "wall render rss_kb" to $out/RENDERER.times, or prints why it failed and returns 1.
run() {
    local renderer="$1" threads="$2" seed="$3" scene="$4" log="$out/$1.log" status=0
    local pin=()
    ((threads > 1)) || pin=(taskset -c 0)
    local spp_option=()
    [ -z "$spp" ] || spp_option=(--spp "$spp")
    if [ "$renderer" = pbrt ]; then
        /usr/bin/time -f "%e %M" -o "$out/usage" "${pin[@]}" "$pbrt" --nthreads "$threads" \
            --seed "$seed" "${spp_option[@]}" --outfile "$out/pbrt-$seed.exr" "$scene" \
            > "$log" 2>&1 || status=$?
    else
        /usr/bin/time -f "%e %M" -o "$out/usage" "${pin[@]}" "$build/nori" --threads "$threads" \
            --seed "$seed" "${spp_option[@]}" --no-progress --checkpoint off \
            -o "$out/nori-$seed" "$scene" > "$log" 2>&1 || status=$?
    fi
    if ((status)); then
        local how="exit status $status"
        ((status <= 128)) || how+=", signal SIG$(kill -l $((status - 128)))"
        echo "   $renderer failed on $(basename "$scene") ($how); left out for this scene." \
             "Its last lines:"
        tr '\r' '\n' < "$log" | grep -v '^ *$' | tail -n 5 | sed 's/^/      /'
        [ -s "$log" ] || echo "      (none)"
        return 1
    fi
    local render wall rss
    if [ "$renderer" = pbrt ]; then # the progress bar's last "(12.3s)", without "|"
        render="$(tr '\r' '\n' < "$log" | sed -nE 's/.*\(([0-9.]+)s\) *$/\1/p' | tail -n 1)"
    else
        render="$(awk -f "$here/scripts/done_seconds.awk" "$log")"
    fi
    read -r wall rss < <(tail -n 1 "$out/usage")
    echo "$wall ${render:-$wall} $rss" >> "$out/$renderer.times"
}

# variance RENDERER SEED_A SEED_B: appends MSE(a, b)/2 to $out/RENDERER.variances.
variance() {
    "$build/nori-imgtool" diff "$out/$1-$2.exr" "$out/$1-$3.exr" |
        awk '$1 == "rmse" { print $2 * $2 / 2 }' >> "$out/$1.variances"
}

# summary RENDERER: one line of medians and ranges; sets efficiency (empty if it failed).
summary() {
    efficiency=""
    [ -s "$out/$1.times" ] && [ -s "$out/$1.variances" ] || { printf '%-6s failed\n' "$1"; return; }
    local line
    line="$(awk -v name="$1" -v variances="$out/$1.variances" '
        function median(v, n,    i, j, x) {
            for (i = 2; i <= n; ++i) for (j = i; j > 1 && v[j - 1] > v[j]; --j) { x = v[j]; v[j] = v[j - 1]; v[j - 1] = x }
            return (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
        }
        { ++n; first[n] = $1 - $2; render[n] = $2; rss[n] = $3 / 1024 }
        END {
            m = 0; sum = 0
            while ((getline v < variances) > 0) { var[++m] = v; sum += v }
            mean = sum / m; ss = 0
            for (i = 1; i <= m; ++i) ss += (var[i] - mean) ^ 2
            se = (m > 1) ? sqrt(ss / (m - 1) / m) : 0
            f = median(first, n); r = median(render, n); p = median(rss, n)
            printf "%-6s %7.2f %6.2f-%-6.2f %8.2f %7.2f-%-7.2f %7.0f %5.0f-%-5.0f %10.3e ± %8.2e %11.4g\n",
                name, f, first[1], first[n], r, render[1], render[n], p, rss[1], rss[n], mean, se,
                1 / (r * mean)
        }' "$out/$1.times")"
    efficiency="${line##* }"
    echo "$line"
}

for scene in "${scenes[@]}"; do
    failed=" " # the renderers that failed on this scene, not run on it again
    for threads in $thread_counts; do
        echo "== $(basename "$scene"), $threads thread$( ((threads > 1)) && echo s || echo ", pinned to core 0")," \
             "$rounds rounds of 2 seeds${spp:+, $spp spp}"
        rm -f "$out"/*.times "$out"/*.variances
        for round in $(seq 1 "$rounds"); do
            a=$((2 * round - 1)) b=$((2 * round))
            for seed in "$a" "$b"; do
                for renderer in pbrt nori; do
                    [[ "$failed" == *" $renderer "* ]] ||
                        run "$renderer" "$threads" "$seed" "$scene" || failed+="$renderer "
                done
            done
            for renderer in pbrt nori; do
                [[ "$failed" == *" $renderer "* ]] || variance "$renderer" "$a" "$b"
            done
        done
        printf '%-6s %22s %24s %19s %23s %11s\n' "" "first pixel (s)" "render (s)" "peak RSS (MB)" \
            "variance ± s.e." "efficiency"
        summary pbrt
        pbrt_efficiency="$efficiency"
        summary nori
        if [ -n "$pbrt_efficiency" ] && [ -n "$efficiency" ]; then
            awk -v n="$efficiency" -v p="$pbrt_efficiency" \
                'BEGIN { printf "nori / pbrt-v4 efficiency: %.2fx\n", n / p }'
        fi
    done
done
