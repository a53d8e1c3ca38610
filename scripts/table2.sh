#!/usr/bin/env bash
# The paper's Table 2, reproduced and beaten: every search method on Models A, B and C
# from the scene files' start points, one `fird optimize --json` run each, then one
# Markdown table (docs/optimization.md shows it). The grid and the single NLopt methods
# run at 1e6 rays per evaluation (the paper's Table 1: enough to optimize with); auto
# runs its own stages. Takes about 1.5 h on a 2-core machine with lavapipe.
# Usage: scripts/table2.sh [OUT_DIR] [METHODS...]   (default out/table2, every method)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/table2}"
shift || true
methods=("$@")
((${#methods[@]})) || methods=(auto bobyqa sbplx cobyla direct crs2 grid)
fird="${FIRD:-build/release/app/fird}"
[ -x "$fird" ] || scripts/setup.sh release
mkdir -p "$out"
for method in "${methods[@]}"; do
  for model in a b c; do
    args=(--method "$method")
    case "$method" in
      auto) ;;
      grid) args+=(--rays 1e6) ;;
      *) args+=(--rays 1e6 --max-evals 2000) ;;
    esac
    echo "table2: model $model, $method" >&2
    "$fird" optimize "scenes/model_$model.toml" "${args[@]}" --json --out "$out/${model}_$method" \
      > "$out/${model}_$method.json.tmp"
    mv "$out/${model}_$method.json.tmp" "$out/${model}_$method.json"
  done
done
/usr/bin/python3 scripts/table2_markdown.py "$out" > "$out/table2.md.tmp"
mv "$out/table2.md.tmp" "$out/table2.md"
cat "$out/table2.md"
