#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Builds the libFuzzer targets (fuzz/) with clang-14, AddressSanitizer and UBSan into build-fuzz
# (static libraries: clang links the sanitizer runtimes into executables only). Used by the gating
# replay (scripts/fuzz-regression.sh) and by exploratory fuzzing (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (when installed) makes a rebuild in a fresh clone cheap: paths are taken relative to here.
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$(pwd)"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-fuzz "${launcher[@]}" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g" \
  -DHYDROTEX_FUZZ=ON -DHYDROTEX_SANITIZE=ON -DHYDROTEX_BUILD_TESTS=OFF -DHYDROTEX_BUILD_DEMOS=OFF \
  -DHYDROTEX_BUILD_GPU=OFF -DBUILD_SHARED_LIBS=OFF >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzz_mesh fuzz_scene
