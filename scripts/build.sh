#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Configures and builds hydrotex (Release) into ./build, using every core; through ccache when it
# is installed (scripts/install-deps.sh installs it), so that a fresh clone rebuilds cheaply.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$(pwd)"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build "${launcher[@]}" -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build build -j "$(nproc)"
