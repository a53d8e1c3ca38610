#!/usr/bin/env bash
# Installs what FIRD needs from Debian 12's packages (only what is missing), then
# configures and builds. Idempotent: a second run installs and rebuilds nothing that
# is up to date. Usage: scripts/setup.sh [release|sanitize|fuzz]   (default: release)
set -euo pipefail
cd "$(dirname "$0")/.."

flavour="${1:-release}"
packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglfw3-dev libglm-dev libimgui-dev libcairo2-dev fonts-dejavu-core
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libfmt-dev libnlopt-cxx-dev nettle-dev
  libpagmo-dev
  libvtk9-dev
  openmpi-bin libopenmpi-dev
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev
  libocct-foundation-dev gmsh
  libgtest-dev libgmock-dev libbenchmark-dev libeigen3-dev
  xvfb xauth xdotool
  xz-utils  # scripts/gpu_bundle.sh packs the build for a GPU machine as .tar.xz
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

case "$flavour" in
  release) dir=build/release; flags=(-DCMAKE_BUILD_TYPE=Release) ;;
  fuzz) dir=build/fuzz; export CC=clang CXX=clang++; flags=(-DFIRD_FUZZ=ON) ;;
  sanitize) dir=build/sanitize; flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRD_SANITIZE=ON -DFIRD_BUILD_UI=OFF -DFIRD_BUILD_BENCH=OFF) ;;
  *) echo "setup: unknown flavour '$flavour' (release, sanitize or fuzz)" >&2; exit 2 ;;
esac
[ -f "$dir/build.ninja" ] || cmake -S . -B "$dir" -G Ninja "${flags[@]}"
cmake --build "$dir" --parallel "$(nproc)"
