#!/usr/bin/env bash
# Rewrites the golden images of tests/render/views_test.cpp from the current build
# (lavapipe), after a deliberate change to a view. Review the new images before committing.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build/release --target test_render
FIRD_UPDATE_GOLDENS=1 build/release/tests/test_render --gtest_filter='Views.*Golden*'
git status --short tests/render/golden
# The workbench frame at three window sizes (tests/ui/workbench_golden_test.cpp).
if [ -f build/release/tests/test_ui_golden ] || grep -q test_ui_golden build/release/build.ninja; then
  cmake --build build/release --target test_ui_golden
  XDG_DATA_HOME=/tmp/fird-workbench-golden/data XDG_CONFIG_HOME=/tmp/fird-workbench-golden/config \
    FIRD_UPDATE_GOLDENS=1 build/release/tests/test_ui_golden
  git status --short tests/ui/golden
fi
