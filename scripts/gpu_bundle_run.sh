#!/usr/bin/env bash
# Runs what scripts/gpu_bundle.sh packed, on a GPU machine without Debian's packages: the
# Vulkan test binaries with validation on the real driver (one log each), then
# scripts/gpu_check.sh's table with the packed fird (no build, no ctest there), into OUTDIR.
# Run from the repository root (the tests read the scenes and goldens in it).
#
# Usage: scripts/gpu_bundle_run.sh DIR OUTDIR [--tests-only | gpu_check.sh options, e.g. --quick]
# (GTEST_FILTER, where set, picks the tests as for any GoogleTest binary.)
# Each test binary is bounded by GPU_BUNDLE_TEST_LIMIT_S (default 80) seconds, and each of
# gpu_check.sh's steps by GPU_CHECK_STEP_LIMIT_S where set (a device call runs at most 10
# minutes: six binaries' limits and the table must fit in it).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dir="${1:?usage: gpu_bundle_run.sh DIR OUTDIR}"
out="${2:?usage: gpu_bundle_run.sh DIR OUTDIR}"
shift 2
tests_only=0 check_args=()
for a in "$@"; do
  if [ "$a" = --tests-only ]; then tests_only=1; else check_args+=("$a"); fi
done
[ -f "$dir/fird_bundle.tar.xz" ] || { echo "gpu_bundle_run.sh: no $dir/fird_bundle.tar.xz (scripts/gpu_bundle.sh makes it)" >&2; exit 1; }
mkdir -p "$out"
out="$(cd "$out" && pwd)"
b="$(mktemp -d /tmp/fird_bundle.XXXXXX)" || exit 1
trap 'rm -rf "$b"' EXIT
# xz may be missing there; Python's tarfile reads it too.
if command -v xz >/dev/null; then
  tar -C "$b" -xJf "$dir/fird_bundle.tar.xz" || exit 1
else
  python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])' \
    "$dir/fird_bundle.tar.xz" "$b" || exit 1
fi
# The bundle's libraries for its own programs only (the machine's python3 must keep its own
# libexpat and libz): each runs through `with_bundle`, fird through a wrapper.
with_bundle() { LD_LIBRARY_PATH="$b/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$@"; }
printf '#!/bin/sh\nexport LD_LIBRARY_PATH="%s/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"\nexec "%s/bin/fird" "$@"\n' \
  "$b" "$b" >"$b/fird"
chmod +x "$b/fird"
export VK_LAYER_PATH="$b/layers"
export FONTCONFIG_FILE="$b/fonts/fonts.conf"
# NVIDIA's driver manifest where the loader's search paths have none (the lent machines).
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
icd_found=0
for d in /usr/share /usr/local/share /etc /usr/local/etc; do
  compgen -G "$d/vulkan/icd.d/*.json" >/dev/null && icd_found=1
done
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && [ -f "$nvidia_icd" ] && ((!icd_found)); then
  export VK_DRIVER_FILES="$nvidia_icd"
fi
# The test binaries read the scenes and goldens at the source path they were built in:
# made to lead here where it does not exist.
read -r src <"$b/built_paths"
if [ "$src" != "$root" ] && [ ! -e "$src" ]; then
  mkdir -p "$(dirname "$src")" && ln -s "$root" "$src" ||
    echo "gpu_bundle_run.sh: cannot link $src to $root: the tests that read scenes will fail" >&2
fi
info="$("$b/fird" --validation info 2>&1)"
echo "bundle of commit $(cat "$b/commit"); device: $(sed -n 's/^chosen: //p' <<<"$info" | head -1); $(grep -m1 '^validation layers:' <<<"$info")" |
  tee "$out/summary.txt"

failed=0
for t in "$b"/bin/test_*; do
  name="$(basename "$t")"
  (cd "$root" && with_bundle timeout "${GPU_BUNDLE_TEST_LIMIT_S:-80}" "$t" --gtest_brief=1 >"$out/$name.log" 2>&1)
  rc=$?
  line="$(grep -E '^\[  (PASSED|FAILED)  \]' "$out/$name.log" | head -2 | tr '\n' ' ')"
  echo "$name: exit $rc ${line:-(no summary: see $name.log)}" | tee -a "$out/summary.txt"
  ((rc == 0)) || failed=1
done
if ((!tests_only)); then
  "$root/scripts/gpu_check.sh" --no-tests --fird "$b/fird" --out "$out/gpu_check.md" ${check_args[@]+"${check_args[@]}"} || failed=1
  # The table's "test suite: not run" is gpu_check.sh's own (no ctest here): the bundle's
  # tests are these.
  { echo; echo "Vulkan tests of the bundle, validation on (scripts/gpu_bundle_run.sh):"; echo
    sed 's/^/    /' "$out/summary.txt"; } >>"$out/gpu_check.md"
fi
exit "$failed"
