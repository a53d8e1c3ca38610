#!/usr/bin/python3
"""Turns the fird optimize JSON objects of scripts/table2.sh into one Markdown table."""
import json
import os
import sys

PAPER = {"a": (1728, 0.63, 0.599456), "b": (2401, 2.2, 0.975587), "c": (6561, 4.9, 0.245821)}
ORDER = ["grid", "auto", "bobyqa", "sbplx", "cobyla", "direct", "crs2"]


def rays(j):
    return " → ".join(f"{s['rays']:.0e}" for s in j["rays_per_evaluation"]).replace("+0", "")


def row(model, method, j):
    final, noise = j.get("final_l2"), j.get("noise_floor_l2")
    ratio = f"{final / noise:.2f}" if final and noise else "–"
    cost = "; ".join(f"{s['stage']} {s['ms_per_evaluation']:.0f}"
                     for s in j["rays_per_evaluation"])
    params = ", ".join(f"{k} {v:g}" for k, v in j["best_parameters"].items())
    return (f"| {model.upper()} | {method} | {j['evaluations']} | {j['infeasible']} | {rays(j)} | "
            f"{j['time_s']:.0f} | {j['best_l2']:.4f} | {final:.4f} | {noise:.4f} | {ratio} | "
            f"{j['surface_rms_mm']:.3f} | {params} | {cost} |")


def main():
    out = sys.argv[1]
    print("| model | method | reflectors tested | infeasible | rays per evaluation | wall s | "
          "best l2 lm | final l2 lm | noise floor lm | final / noise | surface RMS mm | "
          "best parameters | ms per evaluation by stage |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for model in "abc":
        tested, hours, l2 = PAPER[model]
        print(f"| {model.upper()} | paper (2009 GPU) | {tested} | – | – | {hours * 3600:.0f} | "
              f"{l2} | – | – | – | – | – | – |")
        for method in ORDER:
            path = os.path.join(out, f"{model}_{method}.json")
            if os.path.exists(path):
                with open(path) as f:
                    print(row(model, method, json.load(f)))


if __name__ == "__main__":
    main()
