#!/usr/bin/env bash
# The paper's calibration (§5.1) for Models A, B and C: Table 1 (100 runs per ray count)
# and the semivariogram of every parameter (at 1e6 rays), with the cost of each;
# docs/calibration.md shows the results (scripts/calibration_markdown.py OUT_DIR prints its
# tables). About 11 min on a quiet 2-core machine with lavapipe at the defaults, plus 2-3x
# for the semivariograms since their resolvable-step probes (2026-12-02); COUNTS=1e3,...,1e7
# adds the paper's last row (~17 min more). Usage:
#   [COUNTS=1e3,1e4,1e5,1e6] [POINTS=41] scripts/calibration.sh [OUT_DIR] [MODELS...]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/calibration}"
shift || true
models=("$@")
((${#models[@]})) || models=(a b c)
counts="${COUNTS:-1e3,1e4,1e5,1e6}"
points="${POINTS:-41}"
fird="${FIRD:-build/release/app/fird}"
[ -x "$fird" ] || scripts/setup.sh release
mkdir -p "$out"
for model in "${models[@]}"; do
  echo "calibration: model $model, rays" >&2
  "$fird" calibrate rays "scenes/model_$model.toml" --counts "$counts" --runs 100 --json \
    --out "$out/${model}_rays" > "$out/${model}_rays.json.tmp"
  mv "$out/${model}_rays.json.tmp" "$out/${model}_rays.json"
  echo "calibration: model $model, semivariograms" >&2
  "$fird" calibrate semivariogram "scenes/model_$model.toml" --points "$points" --rays 1e6 --json \
    --out "$out/${model}_sv" --write-steps "$out/model_${model}_calibrated.toml" \
    > "$out/${model}_sv.json.tmp"
  mv "$out/${model}_sv.json.tmp" "$out/${model}_sv.json"
done
