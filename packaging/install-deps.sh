#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs every build, run and test dependency of PalletBallet Console from Debian 12 packages.
# Idempotent and non-interactive: a second run installs nothing. Needs root (or sudo).
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # core: physics, linear algebra, JSON (libqhull-dev: mujocoConfig.cmake names /usr/include/libqhull_r)
  libmujoco-dev libqhull-dev libeigen3-dev nlohmann-json3-dev
  # the service: HTTP/1.1 (cpp-httplib) and its command line (CLI11)
  libcpp-httplib-dev libcli11-dev
  # console: Qt 6 Widgets, Test, Charts, OpenGL widgets
  qt6-base-dev qt6-base-dev-tools qt6-charts-dev libqt6opengl6-dev libgl-dev
  # headless GUI tests: a real X server with Mesa's software OpenGL (llvmpipe)
  xvfb xauth libgl1-mesa-dri libglx-mesa0 libegl-mesa0 mesa-utils
  # fonts, so screenshots have readable text
  fonts-dejavu-core
  # CI's fuzz preset: clang 14 and its libFuzzer runtime (tests/fuzz); the format check
  clang-14 libclang-rt-14-dev clang-format-14
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=()
[ "$(id -u)" -eq 0 ] || sudo=(sudo)
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
