#!/usr/bin/env bash
# Builds hydrotex with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan and runs every
# CTest suite there. -O1 (not -O3): the sanitizers' reports stay readable, the build is about twice
# as fast, and assertions stay on (no NDEBUG). Any UB report or leak fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
start=$(date +%s)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1" -DHYDROTEX_SANITIZE=ON >/dev/null
cmake --build build-asan -j "$(nproc)"
built=$(date +%s)

# halt_on_error: the first UB report fails the test instead of scrolling past. Leaks are reported
# (detect_leaks) except those the suppression file lists: allocations Mesa's EGL/llvmpipe driver
# makes once per process and never frees (see the file); ours are not suppressed.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
# package_find_package installs the library and builds a consumer without the sanitizer runtime
# (a packaging test, run in build/); everything else runs here.
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E '^package_find_package$'
echo "test-sanitizers: build $((built - start)) s, tests $(($(date +%s) - built)) s"
