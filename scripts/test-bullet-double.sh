#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Builds the Bullet plugin against Debian's double-precision Bullet (libBullet*-float64,
# -DHYDROTEX_BULLET_DOUBLE=ON) into build-double and runs the plugin suites and the hard cases
# there (the far-from-origin case holds tighter in double): `build`, then `run` (no argument: both).
# Core does not see Bullet, so through ccache only the plugin and these suites compile anew.
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
suites='^(plugin_test_.*|robustness_test_hard_cases)$'
if [ "$what" = build ] || [ "$what" = all ]; then
  launcher=()
  if command -v ccache >/dev/null; then
    export CCACHE_BASEDIR="$(pwd)"
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B build-double "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DHYDROTEX_BULLET_DOUBLE=ON -DHYDROTEX_BUILD_GPU=OFF >/dev/null
  mapfile -t targets < <(cmake --build build-double --target help | sed -n 's/^\.\.\. \([A-Za-z0-9_]*\).*/\1/p' | grep -E "$suites")
  cmake --build build-double -j "$(nproc)" --target hydrotex "${targets[@]}"
fi
if [ "$what" = run ] || [ "$what" = all ]; then
  ctest --test-dir build-double --output-on-failure -j "$(nproc)" -R "$suites"
fi
