#!/usr/bin/env python3
"""The real-target table of docs/optimization.md from scripts/real_targets.sh's JSON files
(read by key): per target and family the final candela_l2 against its noise floor, the
efficiency, the beam angles (C0/C90) against the file's, the surface RMS moved from the
start, evaluations and wall time."""
import json
import math
import os
import sys
import tomllib

out = sys.argv[1]
rows = []
for name in sorted(os.listdir(out)):
    if not name.endswith(".json") or name.endswith(".wall.json"):
        continue
    stem = name[: -len(".json")]
    with open(os.path.join(out, name)) as f:
        j = json.load(f)
    wall = None
    if os.path.exists(os.path.join(out, stem + ".wall.json")):
        with open(os.path.join(out, stem + ".wall.json")) as f:
            wall = json.load(f)["wall_s"]
    target, family = stem.split("_", 1)
    p, d = j.get("photometrics") or {}, j.get("desired_photometrics") or {}

    def beam(x):
        return f"{x['beam_angle_deg']['C0']:.1f}/{x['beam_angle_deg']['C90']:.1f}" if x else "-"

    # The surface moved: RMS of the best parameters' heights against the start's, for the
    # height families (h_*), in mm; "-" for the analytic ones.
    with open(os.path.join(out, "scenes", stem + ".toml"), "rb") as f:
        scene = tomllib.load(f)
    best = j.get("best_parameters") or {}
    start = scene["reflector"].get("heights_mm")
    moved = "-"
    if isinstance(start, (int, float)) and best:
        start = [float(start)] * len([k for k in best if k.startswith("h_")])
    if isinstance(start, list) and best:
        keys = sorted(k for k in best if k.startswith("h_"))
        if len(keys) == len(start):
            if family.startswith("profile"):
                order = sorted(keys, key=lambda k: int(k[2:]))
                diffs = [best[k] - start[i] for i, k in enumerate(order)]
            else:
                n = int(round(math.sqrt(len(start))))
                diffs = [best[f"h_{i}_{jj}"] - start[jj * n + i] for jj in range(n) for i in range(n)]
            moved = f"{math.sqrt(sum(x * x for x in diffs) / len(diffs)):.2f}"
    final, floor = j.get("final_l2"), j.get("noise_floor_l2")
    ratio = f"{final / floor:.2f}" if final and floor else "-"
    rows.append((target, family, f"{j.get('start_l2') or 0:.4g}", f"{final or 0:.4g}", ratio,
                 f"{p.get('efficiency', 0):.3f}", beam(p), beam(d), moved, str(j["evaluations"]),
                 f"{wall:.0f}" if wall else f"{j['time_s']:.0f}"))

print("| target | family | start candela_l2 (cd) | final (cd) | final / noise | efficiency | "
      "beam C0/C90 (deg) | file's beam | control RMS moved (mm) | evaluations | wall (s) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| " + " | ".join(r) + " |")
