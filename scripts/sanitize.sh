#!/usr/bin/env bash
# Builds softcut with AddressSanitizer + UndefinedBehaviorSanitizer (preset
# `asan`: -O1 -g, frame pointers, asserts on, UBSan aborts on the first
# finding) into build-asan/ and runs the whole ctest suite under it. Prints
# the build and test wall times. Extra args go to ctest (e.g. -R mesh).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:intercept_tls_get_addr=0"  # see scripts/test.sh
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/hardening/lsan.supp:print_suppressions=0"
t0=$(date +%s)
cmake --preset asan >/dev/null
cmake --build build-asan -j"$jobs"
t1=$(date +%s)
rc=0
(cd build-asan && ctest --output-on-failure --parallel "$jobs" --timeout 900 "$@") || rc=$?
t2=$(date +%s)
echo "sanitize.sh: build $((t1 - t0)) s, tests $((t2 - t1)) s, ctest exit $rc"
exit $rc
