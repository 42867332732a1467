#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# The gating run (CI's .ci/run calls it; the README names it). Stages, each timed:
#   install          scripts/install-deps.sh (Debian packages)
#   build            Release build into build/ (scripts/build.sh)
#   tests            every CTest suite in build/
#   double build     the plugin against double-precision Bullet into build-double/
#   double tests     ... and its suites run there (scripts/test-bullet-double.sh)
#   sanitizer build  the suites again with ASan + UBSan into build-asan/ (scripts/test-sanitizers.sh)
#   sanitizer tests  ... and run there
#   fuzz build       the libFuzzer targets into build-fuzz/ (scripts/fuzz-build.sh)
#   fuzz replay      every kept input once, then a fixed count of generated inputs from a fixed
#                    seed (scripts/fuzz-regression.sh): the same work and verdict in any clone
# Nothing here depends on time or load: speed goals live in the benchmarks, exploratory fuzzing in
# scripts/fuzz.sh. HYDROTEX_SKIP_SANITIZERS=1 and HYDROTEX_SKIP_FUZZ=1 skip those stages (a quick
# local run). Each stage's time is printed at the end, also when a stage fails.
set -euo pipefail
cd "$(dirname "$0")/.."
stage_times=()
run_start=$(date +%s)
print_stage_times() {
  echo "test.sh: stage times (s)"
  for line in "${stage_times[@]}"; do echo "  $line"; done
  echo "  total: $(($(date +%s) - run_start))"
}
trap print_stage_times EXIT
stage() {
  local name=$1 start
  shift
  start=$(date +%s)
  echo "test.sh: == $name"
  if "$@"; then
    stage_times+=("$name: $(($(date +%s) - start))")
  else
    local code=$?
    stage_times+=("$name: $(($(date +%s) - start)) (failed, exit $code)")
    exit "$code"
  fi
}
stage install scripts/install-deps.sh
stage build scripts/build.sh
stage tests ctest --test-dir build --output-on-failure -j "$(nproc)"
stage "double build" scripts/test-bullet-double.sh build
stage "double tests" scripts/test-bullet-double.sh run
if [ "${HYDROTEX_SKIP_SANITIZERS:-0}" != 1 ]; then
  stage "sanitizer build" scripts/test-sanitizers.sh build
  stage "sanitizer tests" scripts/test-sanitizers.sh run
fi
if [ "${HYDROTEX_SKIP_FUZZ:-0}" != 1 ]; then
  stage "fuzz build" scripts/fuzz-build.sh
  stage "fuzz replay" scripts/fuzz-regression.sh
fi
