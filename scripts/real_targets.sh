#!/usr/bin/env bash
# docs/optimization.md's real-target table (issue 26 item 6): each reflector family under
# Model A's source against four luminaire files of the corpus (relative targets, compared
# by candela_l2), one `fird optimize --json --out` each, then one Markdown table.
# Usage: scripts/real_targets.sh [OUT_DIR] [NAME...]   (NAME: e.g. batwing_profile8; default all)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/real_targets}"
shift || true
fird="${FIRD:-build/release/app/fird}"
[ -x "$fird" ] || scripts/setup.sh release
mkdir -p "$out"
/usr/bin/python3 scripts/real_targets.py "$out/scenes" > /dev/null
names=("$@")
if ((${#names[@]} == 0)); then
  for f in "$out"/scenes/*.toml; do names+=("$(basename "$f" .toml)"); done
fi
for name in "${names[@]}"; do
  [ -f "$out/$name.json" ] && continue
  echo "real targets: $name" >&2
  start=$(date +%s.%N)
  "$fird" optimize "$out/scenes/$name.toml" --json --out "$out/$name" > "$out/$name.json.tmp"
  end=$(date +%s.%N)
  echo "{\"wall_s\": $(echo "$end - $start" | bc)}" > "$out/$name.wall.json"
  mv "$out/$name.json.tmp" "$out/$name.json"
done
/usr/bin/python3 scripts/real_targets_markdown.py "$out" > "$out/real_targets.md.tmp"
mv "$out/real_targets.md.tmp" "$out/real_targets.md"
cat "$out/real_targets.md"
