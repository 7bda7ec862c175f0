#!/usr/bin/env bash
# Runs every test of a sanitizer build (MULTICAGE_SANITIZE=address,undefined) with the
# sanitizer options of docs/robustness.md: leaks checked at the exit of every test process,
# suppressions only for third-party libraries (tests/robustness/lsan.supp), UBSan fatal.
#   bash tests/robustness/run_sanitized_tests.sh build-asan
set -euo pipefail
build=${1:?usage: run_sanitized_tests.sh BUILD_DIR}
here=$(cd "$(dirname "$0")" && pwd)
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1
export LSAN_OPTIONS=suppressions=$here/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$build" --output-on-failure --parallel 2 --timeout 1500
