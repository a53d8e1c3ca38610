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

With --before PATH (another build's fird, e.g. one built in a git worktree of an older
commit), each round also runs that build's two commands beside this build's (which of the
two goes first alternates from round to round), and the table gains its figures and this
build's ratio to it (issue 24 item 6: side by side with the build before and with the
yardstick, in one run).

Usage: scripts/yardstick_ratio.py [--yardstick PATH] [--fird PATH] [--before PATH]
                                  [--runs N] [--models abc]
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
    ap.add_argument("--before", help="a second fird build, run alternately with this one")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--models", default="abc")
    a = ap.parse_args()
    if a.before and os.path.realpath(a.before) == os.path.realpath(a.fird):
        ap.error("--before: the same program as --fird")
    cpu = cpu_model()
    print(f"Side by side, {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {os.cpu_count()} cores ({cpu}); "
          f"{a.runs} alternating pairs per figure, medians.\n")
    builds = [a.fird] + ([a.before] if a.before else [])
    head = ("| model | fird trace s | embree_trace s | whole evaluation ratio | FIRD per candidate ms "
            "(1e6 rays) | yardstick trace ms (1e6 rays) | per-candidate ratio |")
    if a.before:
        head += (" before: trace s | before: whole evaluation ratio | before: candidate ms | "
                 "before: per-candidate ratio | this / before, whole | this / before, candidate |")
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    med = statistics.median
    for m in a.models:
        scene = f"scenes/bench/model_{m}_target.toml"
        whole = {b: [] for b in builds}
        cand = {b: [] for b in builds}
        ys_s, ys_trace = [], []
        for r in range(a.runs):
            order = builds if r % 2 == 0 else builds[::-1]  # neither build always first
            for b in order:
                whole[b].append(run([b, "trace", scene])[0])
            ys_s.append(run([a.yardstick, "--model", m.upper(), "--rays", str(RAYS[m]), "--seed", "1"])[0])
            for b in order:
                with tempfile.TemporaryDirectory() as d:
                    run([b, "bench", "--candidates", f"scenes/model_{m}.toml", "--rays", "1000000",
                         "--reps", "5", "--out", d])
                    with open(os.path.join(d, "candidates.csv")) as f:
                        cand[b].append(float(next(csv.DictReader(f))["candidate_ms"]))
            _, out = run([a.yardstick, "--model", m.upper(), "--rays", "1000000", "--seed", "1"])
            ys_trace.append(json.loads(out)["timings_ms"]["trace_bin"])

        def ratio(xs, ys):  # the median of the pairwise ratios (pairs from one round)
            return med(x / y for x, y in zip(xs, ys))

        row = (f"| {m.upper()} | {med(whole[a.fird]):.2f} | {med(ys_s):.2f} | {ratio(whole[a.fird], ys_s):.2f} | "
               f"{med(cand[a.fird]):.0f} | {med(ys_trace):.0f} | {ratio(cand[a.fird], ys_trace):.2f} |")
        if a.before:
            b = a.before
            row += (f" {med(whole[b]):.2f} | {ratio(whole[b], ys_s):.2f} | {med(cand[b]):.0f} | "
                    f"{ratio(cand[b], ys_trace):.2f} | **{ratio(whole[a.fird], whole[b]):.3f}** | "
                    f"**{ratio(cand[a.fird], cand[b]):.3f}** |")
        print(row, flush=True)


if __name__ == "__main__":
    main()
