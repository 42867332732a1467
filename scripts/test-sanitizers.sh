#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Builds hydrotex with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan and runs the
# CTest suites there: `scripts/test-sanitizers.sh build`, then `scripts/test-sanitizers.sh run`
# (no argument: both). -O1 (not -O3): the reports stay readable, the build is faster, and
# assertions stay on (no NDEBUG). Any UB report, memory error or leak of ours fails the run.
#
# Built: every test executable, the tool and the accuracy report they run (not the benchmarks or
# the renderer). Not run here, each with its reason:
#   package_*             install (cmake --install, the Debian package) and build a consumer
#                         without the sanitizer runtime (packaging, run in build/);
#   demo_*                render whole demos through Mesa's llvmpipe (smoke tests, the --window
#                         runs under Xvfb), minutes each when instrumented; the physics they drive
#                         is what the suites cover here.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
what=${1:-all}
# The plugin suites' GL reruns (plugin_test_*_gl) run the same executables as their CPU runs,
# which are here, with the GL backend that tests/gpu and tests/backends check here: rerunning
# them under ASan on llvmpipe would add minutes to CI and no code.
excluded='^(package_.*|demo_.*|plugin_test_.*_gl)$'

if [ "$what" = build ] || [ "$what" = all ]; then
  launcher=()
  if command -v ccache >/dev/null; then
    export CCACHE_BASEDIR="$root"
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B build-asan "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1" -DHYDROTEX_SANITIZE=ON >/dev/null
  known_targets=$(cmake --build build-asan --target help | sed -n 's/^\.\.\. \([A-Za-z0-9_]*\).*/\1/p')
  targets=(hydrotex hydrotex_accuracy_report)
  for test in $(ctest --test-dir build-asan -N | sed -n 's/^ *Test *#[0-9]*: //p'); do
    if [[ ! $test =~ $excluded ]] && grep -qx "$test" <<<"$known_targets"; then targets+=("$test"); fi
  done
  cmake --build build-asan -j "$(nproc)" --target "${targets[@]}"
fi

if [ "$what" = run ] || [ "$what" = all ]; then
  # halt_on_error: the first UB report fails the test instead of scrolling past. Leaks are reported
  # (detect_leaks) except those the suppression file lists: third-party code only (assimp's error
  # paths; see the file). The EGL/llvmpipe suites run with leak detection too: Mesa leaks nothing.
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
  export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E "$excluded"
fi
