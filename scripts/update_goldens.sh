#!/usr/bin/env bash
# Rewrites the golden images of tests/render/views_test.cpp from the current build
# (lavapipe), after a deliberate change to a view. Review the new images before committing.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build/release --target test_render
FIRD_UPDATE_GOLDENS=1 build/release/tests/test_render --gtest_filter='Views.*Golden*'
git status --short tests/render/golden
