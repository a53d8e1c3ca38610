#!/usr/bin/env python3
"""The tailored-start table of docs/optimization.md from scripts/tailored_start.sh's files:
per scene the search from the scene's start and from --start tailored side by side (the
same seed, stages and desired far field, so the stages' metrics compare between them):
the metric at the start (scene fidelity), the final (fresh rays) against its noise floor,
evaluations, the search's own time (time_s) and the command's wall time (with the --out
files: the part's CAD fit and the candidates' reflectors.pvd), and the evaluations each needed to come within 5 % of the scene
start's best at the scene's fidelity ("-": never): in the stages with the last stage's rays,
seed and far-field grid (auto's CMA-ES run's last stage and its polish, whose bests compare)."""
import csv
import json
import os
import sys

out = sys.argv[1]


def load(run):
    with open(os.path.join(out, run + ".json")) as f:
        j = json.load(f)
    wall = {}
    if os.path.exists(os.path.join(out, run + ".wall.json")):
        with open(os.path.join(out, run + ".wall.json")) as f:
            wall = json.load(f)
    with open(os.path.join(out, run, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return j, wall, rows


def scene_fidelity(j):
    """The stages traced as the last one is (its rays, seed and far-field grid)."""
    last = j["rays_per_evaluation"][-1]
    same = ("rays", "seed", "farfield")
    return [st for st in j["rays_per_evaluation"]
            if all(st.get(k) == last.get(k) for k in same) and st.get("best_l2") is not None]


def reached(rows, stages, metric_key, level):
    """The first evaluation (1-based count) in `stages` whose metric is at or below level."""
    for r in rows:
        if r["stage_name"] in stages and r["feasible"] == "1" and float(r[metric_key]) <= level:
            return int(r["index"]) + 1
    return None


print("| scene | start | CMA-ES sigma0 | stages (rays) | metric at start (cd) | final (cd) | final / noise | evaluations | "
      "to within 5 % of the scene start's best | search (s) | wall (s) | load |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
names = sorted({n.split(".")[0] for n in os.listdir(out) if n.endswith(".scene.json")})
for name in names:
    # Variants beside the two (tailored-<what>: other settings from the tailored start, run
    # by hand into the same folder), after them.
    starts = ["scene", "tailored"] + sorted(
        n[len(name) + 1:-len(".json")] for n in os.listdir(out)
        if n.startswith(name + ".tailored-") and n.endswith(".json") and not n.endswith(".wall.json"))
    starts = [s for s in starts if os.path.exists(os.path.join(out, f"{name}.{s}.json"))]
    if len(starts) < 2:
        continue
    runs = {s: load(f"{name}.{s}") for s in starts}
    j0, _, rows0 = runs["scene"]
    key = f"{j0['metric']}_{j0['metric_unit']}"
    level = 1.05 * min(st["best_l2"] for st in scene_fidelity(j0))
    for start, (j, wall, rows) in runs.items():
        # Each run's own stages at the last one's fidelity (a one-stage run's is at the
        # scene's too, with rays of another stream).
        n = reached(rows, {st["stage"] for st in scene_fidelity(j)}, key, level)
        ratio = j["final_l2"] / j["noise_floor_l2"] if j.get("final_l2") else None
        p = j.get("population") or {}
        stages = "+".join(f"{st['rays']:.0e}".replace("e+0", "e") for st in j["rays_per_evaluation"])
        variant = start.split("-", 1)[1] if "-" in start else ""
        print(f"| {name} | {start.split('-')[0]}"
              + (f" ({j['start']['edge_ray']}{'; ' + variant if variant else ''})"
                 if start != "scene" else "")
              + f" | {p.get('sigma0') or '-'} | {stages}"
              + f" | {j['start']['metric_at_start']:.4g} | {j['final_l2']:.4g} | "
              f"{ratio:.2f} | {j['evaluations']} | {n if n else '-'} | {j['time_s']:.0f} | "
              f"{wall.get('wall_s', j['time_s']):.0f} | {wall.get('load', '-')} |")
