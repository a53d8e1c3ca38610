#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install, build, run the headless demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh release
./build/release/app/fird info
