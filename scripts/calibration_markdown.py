#!/usr/bin/python3
"""Prints docs/calibration.md's tables from the JSON files of scripts/calibration.sh.

Usage: scripts/calibration_markdown.py OUT_DIR [MODELS...]   (default models: a b c)
"""
import json
import math
import os
import sys
import tomllib

# The paper's Table 1 (Model A): rays -> (mean, variance) of its l2 error.
PAPER_TABLE1 = {1000: (271.68, 15078.60), 10000: (27.97, 20.97), 100000: (2.91, 0.04),
                1000000: (0.38, 6e-4), 10000000: (0.13, 3e-7)}


def header(columns):
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))


def rays_table(out, models):
    header(["model", "sampler", "rays", "mean l2 lm", "variance lm²", "predicted lm",
            "mean / predicted", "independent rays (multinomial) lm", "mean² lm²",
            "paper (Model A) mean", "runs", "time s"])
    for m in models:
        with open(os.path.join(out, f"{m}_rays.json")) as f:
            j = json.load(f)
        for r in j["rows"]:
            paper = PAPER_TABLE1.get(r["rays"], ("–",))[0] if m == "a" else "–"
            print(f"| {m.upper()} | {j['sampler']} | {r['rays']:.0e} | {r['mean_l2']:.4g} | "
                  f"{r['var_l2']:.3g} | {r['predicted_l2']:.4g} ({j['prediction']}) | "
                  f"{r['mean_l2'] / r['predicted_l2']:.3f} | {r['multinomial_l2']:.4g} | "
                  f"{r['mean_l2'] ** 2:.4g} | {paper} | {r['runs']} | {r['time_s']:.1f} |")
        print(f"| {m.upper()} | | slope {j['slope']:.3f} | desired: {j['desired_rays']:.0e} rays "
              f"| | | | | | | | {j['time_s']:.0f} (table) |")


def probe_at_step(p):
    """The probe nearest the resolvable step (in log lag): its signal and same-rays sd."""
    step, probes = p["resolvable_step"], p.get("resolution", [])
    if step is None or not probes:
        return None
    return min(probes, key=lambda q: abs(math.log(q["lag"] / step)))


def steps_table(out, models):
    header(["model", "parameter", "scene step", "bounds", "model", "sill lm²", "range",
            "resolvable step (95 %)", "signal / same-rays sd there", "probes",
            "written step", "time s"])
    for m in models:
        with open(os.path.join(out, f"{m}_sv.json")) as f:
            sv = json.load(f)
        with open(f"scenes/model_{m}.toml", "rb") as f:
            opt = tomllib.load(f)["reflector"]["optimize"]
        for p in sv["parameters"]:
            o, fit = opt[p["parameter"]], p["model"]
            res = p["resolvable_step"]
            res = "none" if res is None else f"{res:.3g}"
            q = probe_at_step(p)
            there = "–" if q is None or not q["noise_sd_lm"] else (
                f"{q['signal_lm']:.2g} / {q['noise_sd_lm']:.2g} lm at {q['lag']:.3g}")
            print(f"| {m.upper()} | {p['parameter']} | {o['step']:g} | {o['min']:g} – {o['max']:g} | "
                  f"{fit['type']} | {fit['sill']:.3g} | {fit['range']:.3g} | {res} | {there} | "
                  f"{len(p.get('resolution', []))} | {p['calibrated_step']:.3g} | {p['time_s']:.1f} |")
        fresh = math.sqrt(2.0 * sv["noise_variance_l2"])
        print(f"| {m.upper()} | fresh-ray noise: variance {sv['noise_variance_l2']:.3g} lm² "
              f"(difference sd {fresh:.2g} lm), {sv['points']} points | | | | | | | | | "
              f"{sv.get('step_rule', 'range')} | {sv['time_s']:.0f} (all) |")


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: calibration_markdown.py OUT_DIR [MODELS...]")
    out, models = sys.argv[1], sys.argv[2:] or ["a", "b", "c"]
    rays_table(out, models)
    print()
    steps_table(out, models)


if __name__ == "__main__":
    main()
