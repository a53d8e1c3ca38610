#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install, build, run the headless demo:
# one lighting evaluation of the paper's Model A on the fast path (Vulkan; lavapipe on
# a CPU-only machine), with its target, pictures in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh release
./build/release/app/fird info
./build/release/app/fird trace scenes/model_a.toml --out out/
echo "demo: pictures in out/farfield.png, out/target.png, out/difference.png; data in out/*.npy"
