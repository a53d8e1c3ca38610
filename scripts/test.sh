#!/usr/bin/env bash
# All the tests on a fresh Debian 12 machine: install, build, run the suite (with the
# Vulkan validation layers on), then the same suite under AddressSanitizer and
# UndefinedBehaviorSanitizer, then the photometric readers' libFuzzer targets (clang) for
# a bounded time each. `scripts/test.sh --no-sanitize` skips the last two.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

# Each stage from an empty shader cache of its own: lavapipe's on-disk cache keys a
# shader without the vector width it was compiled for, so a variant cached by an earlier
# run in another configuration could hide a compile that crashes in this one
# (docs/architecture.md, "CPU vector width"; FIRD's 512-bit commands keep theirs in a
# folder inside this one).
fresh_shader_cache() {
  rm -rf "$1/mesa_shader_cache"
  export MESA_SHADER_CACHE_DIR="$PWD/$1/mesa_shader_cache"
}

scripts/setup.sh release
fresh_shader_cache build/release
(cd build/release && ctest --output-on-failure -j "$jobs")

if [ "${1:-}" != "--no-sanitize" ]; then
  scripts/setup.sh sanitize
  # ASAN_OPTIONS is set per test by CTest (tests/CMakeLists.txt): leak detection is on
  # for CPU-only tests, off where Mesa's driver is loaded.
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  fresh_shader_cache build/sanitize
  (cd build/sanitize && ctest --output-on-failure -j "$jobs")
  scripts/setup.sh fuzz
  (cd build/fuzz && ctest -L fuzz --output-on-failure -j "$jobs")
fi
