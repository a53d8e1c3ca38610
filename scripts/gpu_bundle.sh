#!/usr/bin/env bash
# Packs the Release build for a GPU machine without Debian's packages (issue 24 item 7: the
# machines lent to a session here are bare, reach nothing, and take at most 64 MiB of files
# a call): fird and the Vulkan test binaries, every shared library they load but glibc's own
# (VTK, OpenCASCADE, ... and libstdc++), the Vulkan loader, the Khronos validation layer
# with its manifest (the tests run with validation on), FIRD's own modules (libfird_*.so)
# and the DejaVu fonts with a fontconfig file (the plots' labels), as one
# fird_bundle.tar.xz in DIR. On the GPU machine,
# from the repository root: scripts/gpu_bundle_run.sh DIR OUTDIR (the tests, then
# scripts/gpu_check.sh's table, into OUTDIR).
#
# Usage: scripts/gpu_bundle.sh [DIR [BUILD]]   (DIR default .gpu; BUILD, a Release build
# folder with its tests built, default build/release). XZ_OPT=-0 packs faster, larger.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dir="${1:-$root/.gpu}"
build="$(cd "${2:-$root/build/release}" && pwd)"
# The Vulkan test binaries (those that create a device), as gpu_check.sh's suite runs them.
tests=(test_vk test_render test_fastpath test_optimize test_calibration test_export)
bins=("$build/app/fird")
for t in "${tests[@]}"; do bins+=("$build/tests/$t"); done
# FIRD's own modules (io/program_files.hpp: libfird_pagmo.so, loaded by a population search;
# libfird_vtk.so and libfird_cad.so, by an export), which the programs look for in the lib
# folder beside their own: the bundle's lib. Their libraries (pagmo, VTK, OpenCASCADE) travel
# with them.
modules=("$build"/lib/libfird_*.so)
for b in "${bins[@]}" "${modules[@]}"; do
  [ -x "$b" ] || { echo "gpu_bundle.sh: no $b (build build/release first: scripts/setup.sh release)" >&2; exit 1; }
done
layer_so=/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so
layer_json=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
loader=/usr/lib/x86_64-linux-gnu/libvulkan.so.1
fonts=/usr/share/fonts/truetype/dejavu
for f in "$layer_so" "$layer_json" "$loader" "$fonts"; do
  [ -e "$f" ] || { echo "gpu_bundle.sh: no $f (install vulkan-validationlayers, libvulkan1, fonts-dejavu-core)" >&2; exit 1; }
done

# The C library's own files: the machine's must match its kernel and loader, so these stay.
glibc='/(libc|libm|libdl|libpthread|librt|libresolv|ld-linux-x86-64)\.so'
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$stage/layers" "$stage/fonts"
cp "${bins[@]}" "$stage/bin/"
# Every library the binaries and the layer load, but the C library's own (the machine's
# must match its kernel and loader; every other one travels, libstdc++ included).
cp "${modules[@]}" "$stage/lib/"
ldd "${bins[@]}" "${modules[@]}" "$layer_so" | awk '/=> \//{print $3}' | sort -u |
  grep -Ev "$glibc" |
  while read -r lib; do cp -L "$lib" "$stage/lib/"; done
cp -L "$loader" "$stage/lib/"
cp -L "$layer_so" "$stage/layers/"
# The manifest names the layer's library beside it (a path relative to the manifest).
sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
  "$layer_json" >"$stage/layers/VkLayer_khronos_validation.json"
cp -r "$fonts" "$stage/fonts/dejavu"
# With this machine's fontconfig rules (hinting, antialiasing: /etc/fonts/conf.d), without
# which the plots' labels render a pixel apart from the goldens made here.
mkdir -p "$stage/fonts/conf.d"
[ -d /etc/fonts/conf.d ] || { echo "gpu_bundle.sh: no /etc/fonts/conf.d (install fontconfig-config)" >&2; exit 1; }
cp -L /etc/fonts/conf.d/*.conf "$stage/fonts/conf.d/"
cat >"$stage/fonts/fonts.conf" <<'EOF'
<?xml version="1.0"?>
<!DOCTYPE fontconfig SYSTEM "fonts.dtd">
<fontconfig>
  <dir prefix="relative">dejavu</dir>
  <include ignore_missing="yes" prefix="relative">conf.d</include>
  <cachedir>/tmp/fird_bundle_fontcache</cachedir>
</fontconfig>
EOF
# Every library must now resolve inside the bundle (but glibc's): a machine without Debian's
# packages has none of them to fall back on.
outside="$(LD_LIBRARY_PATH="$stage/lib" ldd "$stage"/bin/* "$stage"/lib/libfird_*.so "$stage/layers/libVkLayer_khronos_validation.so" |
  awk '/=> \//{print $3} /not found/{print $1 " (not found)"}' | grep -v "^$stage/lib/" |
  grep -Ev "$glibc" | sort -u || true)"
[ -z "$outside" ] || { echo "gpu_bundle.sh: libraries resolved outside the bundle: $outside" >&2; exit 1; }
# The tree the build is of, as it is now (a build older than the tree's last change is not
# rebuilt here: build first).
git -C "$root" describe --always --dirty >"$stage/commit" 2>/dev/null || echo unknown >"$stage/commit"
# The source path the test binaries were built with (FIRD_SOURCE_DIR: tests/CMakeLists.txt).
src="$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null || true)"
echo "${src:-$root}" >"$stage/built_paths"

mkdir -p "$dir"
tar -C "$stage" -cJf "$dir/fird_bundle.tar.xz.tmp" .
mv "$dir/fird_bundle.tar.xz.tmp" "$dir/fird_bundle.tar.xz"
size=$(stat -c %s "$dir/fird_bundle.tar.xz")
echo "gpu_bundle.sh: $dir/fird_bundle.tar.xz, $((size / 1048576)) MiB ($(ls "$stage/lib" | wc -l) libraries, commit $(cat "$stage/commit"))"
# A device call carries at most 64 MiB: the bundle and the tracked tree together.
tree=$(git -C "$root" ls-files -z | (cd "$root" && xargs -0 stat -c %s 2>/dev/null) | awk '{s += $1} END {print s + 0}')
((size + tree < 64 * 1048576)) ||
  echo "gpu_bundle.sh: warning: the bundle and the tracked tree ($((tree / 1048576)) MiB) pass the 64 MiB a device call carries" >&2
