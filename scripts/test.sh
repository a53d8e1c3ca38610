#!/usr/bin/env bash
# All the tests on a fresh Debian 12 machine: install, build, run the suite (with the
# Vulkan validation layers on), then the same suite under AddressSanitizer and
# UndefinedBehaviorSanitizer, then the photometric readers' libFuzzer targets (clang) for
# a bounded time each. `scripts/test.sh --no-sanitize` skips the last two.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

scripts/setup.sh release
(cd build/release && ctest --output-on-failure -j "$jobs")

if [ "${1:-}" != "--no-sanitize" ]; then
  scripts/setup.sh sanitize
  # ASAN_OPTIONS is set per test by CTest (tests/CMakeLists.txt): leak detection is on
  # for CPU-only tests, off where Mesa's driver is loaded.
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  (cd build/sanitize && ctest --output-on-failure -j "$jobs")
  scripts/setup.sh fuzz
  (cd build/fuzz && ctest -L fuzz --output-on-failure -j "$jobs")
fi
