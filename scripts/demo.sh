#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install, build, run the headless demo on the
# paper's Model A (Vulkan; lavapipe on a CPU-only machine): one lighting evaluation with
# its target, then the inverse design itself (fird optimize: the reflector that gives the
# target's far field, found from the scene's start point), then the found reflector
# exported for ParaView. Everything lands in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh release
fird=./build/release/app/fird
"$fird" info
"$fird" trace scenes/model_a.toml --out out/
"$fird" optimize scenes/model_a.toml --out out/optimize
echo "demo: one evaluation: out/farfield.png, out/target.png, out/difference.png, out/*.npy"
echo "demo: the search: out/optimize/ (report, history.csv, progress pictures, best reflector;"
echo "      reflectors.pvd opens in ParaView)"
