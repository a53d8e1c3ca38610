#!/usr/bin/env bash
# The paper's calibration (§5.1) for Models A, B and C: Table 1 (100 runs per ray count,
# 1e3 to 1e7 rays) and the semivariogram of every parameter (101 points at 1e6 rays),
# with the cost of each; docs/calibration.md shows the results. About 40 min on a 2-core
# machine with lavapipe. Usage: scripts/calibration.sh [OUT_DIR] [MODELS...]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/calibration}"
shift || true
models=("$@")
((${#models[@]})) || models=(a b c)
fird="${FIRD:-build/release/app/fird}"
[ -x "$fird" ] || scripts/setup.sh release
mkdir -p "$out"
for model in "${models[@]}"; do
  echo "calibration: model $model, rays" >&2
  "$fird" calibrate rays "scenes/model_$model.toml" --json --out "$out/${model}_rays" \
    > "$out/${model}_rays.json.tmp" && mv "$out/${model}_rays.json.tmp" "$out/${model}_rays.json"
  echo "calibration: model $model, semivariograms" >&2
  "$fird" calibrate semivariogram "scenes/model_$model.toml" --json --out "$out/${model}_sv" \
    --write-steps "$out/model_${model}_calibrated.toml" \
    > "$out/${model}_sv.json.tmp" && mv "$out/${model}_sv.json.tmp" "$out/${model}_sv.json"
done
