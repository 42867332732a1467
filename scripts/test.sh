#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test suite through CTest (build/); then every suite
# again under AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/); then each libFuzzer
# target for a fixed time with a fixed seed on the corpus kept in fuzz/corpus (scripts/fuzz.sh,
# FUZZ_SECONDS=60 each by default). HYDROTEX_SKIP_SANITIZERS=1 and HYDROTEX_SKIP_FUZZ=1 skip those
# stages (a quick local run).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
if [ "${HYDROTEX_SKIP_SANITIZERS:-0}" != 1 ]; then scripts/test-sanitizers.sh; fi
if [ "${HYDROTEX_SKIP_FUZZ:-0}" != 1 ]; then scripts/fuzz.sh; fi
