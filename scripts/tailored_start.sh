#!/usr/bin/env bash
# docs/optimization.md's "A start from the target (tailored)" table (issue 26 item 5): each
# profile scene of scripts/real_targets.py searched twice, from the scene's start and from
# `--start tailored`, same seed and settings, one after the other; then one Markdown table
# (scripts/tailored_start_markdown.py, reading each --json by key and each history.csv by
# header).
# Usage: scripts/tailored_start.sh [OUT_DIR] [NAME...]   (default: downlight and batwing,
# profile8 and profile16)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/tailored_start}"
shift || true
fird="${FIRD:-build/release/app/fird}"
[ -x "$fird" ] || scripts/setup.sh release
mkdir -p "$out"
/usr/bin/python3 scripts/real_targets.py "$out/scenes" > /dev/null
names=("$@")
if ((${#names[@]} == 0)); then
  names=(downlight_profile8 batwing_profile8 downlight_profile16 batwing_profile16)
fi
for name in "${names[@]}"; do
  for start in scene tailored; do
    run="${name}.${start}"
    [ -f "$out/$run.json" ] && continue
    echo "tailored start: $run (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
    begin=$(date +%s.%N)
    "$fird" optimize "$out/scenes/$name.toml" --start "$start" --json --out "$out/$run" \
      > "$out/$run.json.tmp"
    end=$(date +%s.%N)
    echo "{\"wall_s\": $(echo "$end - $begin" | bc), \"load\": \"$(cut -d' ' -f1-3 /proc/loadavg)\"}" \
      > "$out/$run.wall.json"
    mv "$out/$run.json.tmp" "$out/$run.json"
  done
done
/usr/bin/python3 scripts/tailored_start_markdown.py "$out" > "$out/tailored_start.md.tmp"
mv "$out/tailored_start.md.tmp" "$out/tailored_start.md"
cat "$out/tailored_start.md"
