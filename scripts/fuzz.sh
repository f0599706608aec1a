#!/usr/bin/env bash
# Builds the fuzz targets with clang, libFuzzer, ASan and UBSan, and fuzzes each one.
#   scripts/fuzz.sh [--seconds N] [--build DIR] [xml] [obj] [ply] [serialized] [gltf] [pbrt]
#                   [mitsuba] [image] [tga] [lens] [volume] [checkpoint]
# Prints libFuzzer's figures (executions, coverage) and exits non-zero when a target
# crashed, leaked, hit undefined behaviour or threw anything but a NoriException; the
# input that did it is in DIR/artifacts/. New interesting inputs go to DIR/corpus-<target>.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
seconds=600
build="$here/build-fuzz"
targets=()
while (($#)); do
    case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    xml | obj | ply | serialized | gltf | pbrt | mitsuba | image | tga | lens | volume | checkpoint)
        targets+=("$1"); shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see fuzz.sh --help)" >&2; exit 2 ;;
    esac
done
((${#targets[@]})) || targets=(xml obj ply serialized gltf pbrt mitsuba image tga lens volume checkpoint)

# -O1 as libFuzzer's documentation advises; line tables only, which is all the sanitizers'
# stack traces need and builds faster than full debug information; assertions on (no NDEBUG).
# Only the fuzz targets are built, and they link only the areas they read with
# (tests/fuzz/CMakeLists.txt): neither the app area nor the denoiser is compiled.
# Ninja for a new build directory; an existing one keeps the generator it was made with.
generator=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja > /dev/null; then
    generator=(-G Ninja)
fi
cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DNORI_FUZZ=ON -DNORI_BUILD_TESTS=OFF -DNORI_PCH=ON \
    > "$build.configure.log" 2>&1 ||
    { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target $(printf 'nori-fuzz-%s ' "${targets[@]}")

# Fuzzes one target for $seconds s; its report goes to $build/fuzz-TARGET.summary.
fuzz_one() {
    local target="$1" seeds max_len corpus summary="$build/fuzz-$1.summary"
    case "$target" in
    xml) seeds=("$here/tests/badinput" "$here/scenes/tests" "$here/tests/fuzz/corpus/xml") ;;
    obj) seeds=("$here/tests/fuzz/corpus/obj" "$here/tests/badinput" "$here/scenes/cbox/meshes") ;;
    ply) seeds=("$here/tests/fuzz/corpus/ply" "$here/tests/data/meshes") ;;
    image) seeds=("$here/tests/fuzz/corpus/image" "$here/scenes/textured/textures") ;;
    tga) seeds=("$here/tests/fuzz/corpus/tga") ;;
    serialized) seeds=("$here/tests/fuzz/corpus/serialized") ;;
    gltf) seeds=("$here/tests/fuzz/corpus/gltf" "$here/tests/data/meshes") ;;
    pbrt) seeds=("$here/tests/fuzz/corpus/pbrt") ;;
    mitsuba) seeds=("$here/tests/fuzz/corpus/mitsuba" "$here/tests/data/mitsuba") ;;
    lens) seeds=("$here/tests/fuzz/corpus/lens" "$here/scenes/lenses") ;;
    volume) seeds=("$here/tests/fuzz/corpus/volume" "$here/scenes/media") ;;
    checkpoint) seeds=("$here/tests/fuzz/corpus/checkpoint") ;;
    esac
    # The smallest NanoVDB file is about 300 KB (a root, one upper node of 32^3 entries),
    # so the volume target takes inputs up to 1 MiB; the others 64 KiB.
    max_len=65536
    [ "$target" = volume ] && max_len=1048576
    corpus="$build/corpus-$target"
    mkdir -p "$corpus"
    echo "== fuzzed the $target reader for $seconds s" > "$summary"
    # -rss_limit_mb: a single input may not use more than 2 GiB; -timeout: nor take 10 s.
    local status=0
    "$build/nori-fuzz-$target" "$corpus" "${seeds[@]}" -dict="$here/tests/fuzz/$target.dict" \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
        -artifact_prefix="$build/artifacts/$target-" -print_final_stats=1 \
        > "$build/fuzz-$target.log" 2>&1 || status=1
    if ((status)); then
        # The report from its first line (the sanitizer's or libFuzzer's), where the
        # frames that matter are: a long trace cut at its end loses them.
        local report
        report="$(awk '/ERROR: |runtime error: |deadly signal|uncaught exception/ { on = 1 }
                       on && n++ < 60' "$build/fuzz-$target.log")"
        [ -n "$report" ] || report="$(tail -n 60 "$build/fuzz-$target.log")"
        printf 'the %s target failed; its report:\n%s\n' "$target" "$report" >> "$summary"
    fi
    grep -E "^Done|stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$build/fuzz-$target.log" |
        tail -n 4 >> "$summary"
    return $status
}

# One target per core at a time (each libFuzzer process is single-threaded).
mkdir -p "$build/artifacts"
status=0
running=0
for target in "${targets[@]}"; do
    if ((running >= $(nproc))); then
        wait -n || status=1
        running=$((running - 1))
    fi
    echo "== fuzzing the $target reader for $seconds s"
    fuzz_one "$target" &
    running=$((running + 1))
done
while ((running > 0)); do
    wait -n || status=1
    running=$((running - 1))
done
for target in "${targets[@]}"; do
    cat "$build/fuzz-$target.summary"
done
exit $status
