#!/usr/bin/env bash
# Builds the renderer and its tests under sanitizers and runs the whole ctest suite (the
# Catch2 tests and the command-line, bad-input, documentation and plugin tests) under
# each: AddressSanitizer with UndefinedBehaviorSanitizer (build-asan), then
# ThreadSanitizer (build-tsan, with scripts/tsan.supp). A sanitizer report fails its test.
#   scripts/sanitize.sh [--asan] [--tsan] [--prefix DIR] [--jobs N] [-R REGEX]
#                       [--sample-scale S]
#     --asan, --tsan    only that sanitizer (default: both, ASan first)
#     --prefix DIR      build in DIR-asan and DIR-tsan (default: build, beside the sources)
#     --jobs N          compile and test jobs (default: the number of cores)
#     -R REGEX          only the tests whose names match (as ctest -R)
#     --sample-scale S  the statistical tests' samples times S, in (0, 1] (default 1);
#                       exported as NORI_TEST_SAMPLE_SCALE, the tests' one knob, under
#                       which the negative controls keep their power (docs/testing.md).
# Prints the time of every build and test run, and exits non-zero when a build or a test
# failed.
# The fuzzing test (fuzz.libfuzzer) is not part of these builds: it is its own clang
# build under ASan and UBSan, run by the README's test command.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
prefix="$here/build"
jobs="$(nproc)"
sanitizers=()
filter=()
scale=1
while (($#)); do
    case "$1" in
    --asan) sanitizers+=(asan); shift ;;
    --tsan) sanitizers+=(tsan); shift ;;
    --prefix) prefix="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    -R) filter=(-R "$2"); shift 2 ;;
    --sample-scale) scale="$2"; shift 2 ;;
    *) echo "sanitize.sh: unknown argument '$1' (see sanitize.sh --help)" >&2; exit 2 ;;
    esac
done
((${#sanitizers[@]})) || sanitizers=(asan tsan)

# clang, as for the fuzzing build: its instrumented builds compile in half GCC's time
# (a unity file of the core area under ASan and UBSan, 60 s of CPU against 114 s with GCC,
# 2026-12-06), and its sanitizers are the reference ones. -O1 (ASan's advice: the
# optimiser keeps the checks' stack traces readable), with line tables for the reports.
flags="-O1 -gline-tables-only"
# Every report is fatal and names its stack; leaks are reported at exit (ASan's default).
export ASAN_OPTIONS="detect_stack_use_after_return=0:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export NORI_TEST_SAMPLE_SCALE="$scale"
export TSAN_OPTIONS="suppressions=$here/scripts/tsan.supp:second_deadlock_stack=1:history_size=4"

status=0
summary=""
for sanitizer in "${sanitizers[@]}"; do
    build="$prefix-$sanitizer"
    option=ON
    [ "$sanitizer" = tsan ] && option=thread
    generator=()
    if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja > /dev/null; then
        generator=(-G Ninja)
    fi
    start=$(date +%s)
    log="$(mktemp)"
    if ! cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
        -DCMAKE_CXX_FLAGS="$flags" -DNORI_SANITIZE="$option" -DNORI_BUILD_TESTS=ON \
        > "$log" 2>&1; then
        cat "$log"
        rm -f "$log"
        exit 1
    fi
    rm -f "$log"
    if ! cmake --build "$build" -j"$jobs"; then
        echo "sanitize.sh: the $sanitizer build failed" >&2
        exit 1
    fi
    built=$(date +%s)
    result=passed
    ctest --test-dir "$build" -j"$jobs" --output-on-failure "${filter[@]}" || { result=FAILED; status=1; }
    tested=$(date +%s)
    summary+="$(printf '%s: build %d s, tests %d s, %s\n' "$sanitizer" $((built - start)) \
        $((tested - built)) "$result")"$'\n'
done
printf '\nsanitize.sh on %s cores, NORI_TEST_SAMPLE_SCALE=%s:\n%s' "$jobs" "$scale" "$summary"
exit $status
