#!/usr/bin/env bash
# Runs every libFuzzer target of BUILD_DIR for SECONDS each (default 60), from a copy of the
# seed corpus (tests/fuzz/corpus/<target>/; the repository stays untouched), at most two at a
# time. Fails, naming the target and its log, on any finding (crash, sanitizer report, leak,
# timeout of one input over 25 s, or more than 2 GiB).
#   bash tests/fuzz/run_fuzzers.sh build-asan 60
set -euo pipefail
build=${1:?usage: run_fuzzers.sh BUILD_DIR [SECONDS]}
seconds=${2:-60}
src=$(cd "$(dirname "$0")" && pwd)
work="$build/fuzz-ci"
rm -rf "$work"
mkdir -p "$work"
run() {
    local t=$1
    mkdir -p "$work/$t" "$work/artifacts"
    cp "$src/corpus/$t/"* "$work/$t/"
    # Leak checks per input are left to the sanitizer test run (LSan at exit of every test):
    # here they stop the world after each input and cost most of the time.
    if timeout $((seconds + 120)) "$build/bin/$t" -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 \
        -detect_leaks=0 -print_final_stats=1 -artifact_prefix="$work/artifacts/$t-" "$work/$t" \
        > "$work/$t.log" 2>&1; then
        echo "$t: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$t.log" | grep -o '[0-9]*$') inputs in ${seconds} s, no finding"
    else
        echo "$t: FINDING (exit $?): see $work/$t.log and $work/artifacts/"
        tail -40 "$work/$t.log"
        return 1
    fi
}
status=0
run fuzz_cage_file & a=$!
run fuzz_validate & b=$!
wait $a || status=1
wait $b || status=1
run fuzz_deform & a=$!
run fuzz_onnx_input & b=$!
wait $a || status=1
wait $b || status=1
exit $status
