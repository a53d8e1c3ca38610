#!/usr/bin/python3
"""FIRD against the Embree yardstick (../shared/yardstick), side by side.

Runs, alternately and several times, (a) one whole evaluation as a user runs it:
`fird trace scenes/bench/model_X_target.toml` against `embree_trace --model X` (process
start included, the scene's rays, same reflector, no target); and (b) the cost per
candidate inside a search at 1e6 rays: `fird bench --candidates` (wall time of one
evaluation of a changed reflector in a warm process: the rayset kept, height field,
trace, histogram and compare against the target, median of 5) against the yardstick's
`trace_bin` for the same rays (its trace and binning, without ray generation or BVH build).
Prints the median of the pairwise ratios per model (the machine's speed drifts: only
pairs taken side by side are compared).

Usage: scripts/yardstick_ratio.py [--yardstick PATH] [--runs N] [--models abc]
Build the yardstick first as its README says (Embree 3, TBB; not part of FIRD).
"""
import argparse
import csv
import datetime
import json
import os
import platform
import statistics
import subprocess
import tempfile
import time

RAYS = {"a": 10_000_000, "b": 5_000_000, "c": 10_000_000}


def run(cmd):
    t0 = time.monotonic()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return time.monotonic() - t0, out


def cpu_model():
    """The processor's name as /proc/cpuinfo gives it (platform.processor() is empty on Linux)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.machine()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--yardstick", default="/tmp/yardstick/embree_trace")
    ap.add_argument("--fird", default="build/release/app/fird")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--models", default="abc")
    a = ap.parse_args()
    cpu = cpu_model()
    print(f"Side by side, {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {os.cpu_count()} cores ({cpu}); "
          f"{a.runs} alternating pairs per figure, medians.\n")
    print("| model | fird trace s | embree_trace s | whole evaluation ratio | FIRD per candidate ms "
          "(1e6 rays) | yardstick trace ms (1e6 rays) | per-candidate ratio |")
    print("|---|---|---|---|---|---|---|")
    for m in a.models:
        scene = f"scenes/bench/model_{m}_target.toml"
        fird_s, ys_s, ratios = [], [], []
        cand, ys_trace, cand_ratios = [], [], []
        for _ in range(a.runs):
            tf, _ = run([a.fird, "trace", scene])
            ty, _ = run([a.yardstick, "--model", m.upper(), "--rays", str(RAYS[m]), "--seed", "1"])
            fird_s.append(tf)
            ys_s.append(ty)
            ratios.append(tf / ty)
            with tempfile.TemporaryDirectory() as d:
                run([a.fird, "bench", "--candidates", f"scenes/model_{m}.toml", "--rays", "1000000",
                     "--reps", "5", "--out", d])
                with open(os.path.join(d, "candidates.csv")) as f:
                    c = float(next(csv.DictReader(f))["candidate_ms"])
            _, out = run([a.yardstick, "--model", m.upper(), "--rays", "1000000", "--seed", "1"])
            y = json.loads(out)["timings_ms"]["trace_bin"]
            cand.append(c)
            ys_trace.append(y)
            cand_ratios.append(c / y)
        med = statistics.median
        print(f"| {m.upper()} | {med(fird_s):.2f} | {med(ys_s):.2f} | {med(ratios):.2f} | {med(cand):.0f} | "
              f"{med(ys_trace):.0f} | {med(cand_ratios):.2f} |", flush=True)


if __name__ == "__main__":
    main()
