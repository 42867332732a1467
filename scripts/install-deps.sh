#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Installs hydrotex's build and test dependencies from Debian's packages. Idempotent: packages
# already installed are left alone and apt is not touched at all when nothing is missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libassimp-dev libbullet-dev libstb-dev catch2 nlohmann-json3-dev libcli11-dev libtbb-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libepoxy-dev
  libglfw3-dev xvfb xauth
  ffmpeg gnuplot-nox
  clang-14 libclang-rt-14-dev
  ccache
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

cmd=(apt-get install -y --no-install-recommends "${missing[@]}")
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive "${cmd[@]}"
  else
    echo "install-deps: missing packages: ${missing[*]}" >&2
    echo "install-deps: run as root: apt-get update && ${cmd[*]}" >&2
    exit 1
  fi
else
  echo "install-deps: installing ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${cmd[@]}" -qq >/dev/null
fi
