#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test suite through CTest (build/); then every suite
# again under AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/), and each libFuzzer
# target for a fixed time on its corpus (build-fuzz/). HYDROTEX_SKIP_SANITIZERS=1 and
# HYDROTEX_SKIP_FUZZ=1 skip those two stages (e.g. for a quick local run).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
if [ "${HYDROTEX_SKIP_SANITIZERS:-0}" != 1 ]; then scripts/test-sanitizers.sh; fi
if [ "${HYDROTEX_SKIP_FUZZ:-0}" != 1 ]; then scripts/fuzz.sh; fi
