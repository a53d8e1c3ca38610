#!/usr/bin/env python3
"""Writes the scenes of docs/optimization.md's real-target table (issue 26 item 6): Model
A's cylinder source and holder under one reflector family, against one luminaire file of
the photometric corpus as a relative target, compared by candela_l2.

Usage: scripts/real_targets.py OUT_DIR    (prints one line per scene: its path)
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "tests", "photometry", "data", "corpus")

# Four shapes a luminaire maker meets (tests/photometry/data/corpus/SOURCES.md).
TARGETS = {
    "road": "ers_road_luminaire_irregularC.ldt",
    "batwing": "ers_wiki_batwing.ldt",
    "flood": "ers_floodlight_12w_54deg.ies",
    "downlight": "ers_indoor_ovni_latin1.ies",
}

HEADER = """# {title} (scripts/real_targets.py: issue 26's real-target table).
name = "{title}"

[source]
type = "cylinder"
center_mm = [0.0, 0.0, 0.0]
axis = [1.0, 0.0, 0.0]
length_mm = 4.1
radius_mm = 0.65
emittance = "cosine"
flux_lm = 1100.0

[holder]
min_mm = [-30.0, -20.0, -20.0]
max_mm = [30.0, 20.0, 0.0]
"""

TAIL = """
[trace]
rays = 300000
seed = 1
max_bounces = 1
farfield = [360, 180]
heightfield = [300, 200]

[optimize]
metric = "candela_l2"
rays = [100000, 300000]
max_evaluations = {max_evals}

[target]
file = "{target}"
absolute = false
"""


def paraboloid():
    return """
[reflector]
family = "paraboloid"
fx = 13.0
fy = 12.0
z0 = -10.0
cx = 0.0
cy = 0.0

[reflector.optimize]
fx = { min = 4.0, max = 40.0, step = 0.5 }
fy = { min = 4.0, max = 40.0, step = 0.5 }
z0 = { min = -18.0, max = -4.0, step = 0.5 }
"""


def profile(n):
    # The start: Model A's paraboloid about its axis, fx = fy = 12.5 (z = -10 + r^2 / 50).
    radius = 30.0
    heights = [round((radius * k / (n - 1)) ** 2 / 50.0, 3) for k in range(n)]
    return f"""
[reflector]
family = "profile"
z0 = -10.0
cx = 0.0
cy = 0.0
radius_mm = {radius}
heights_mm = {heights}

[reflector.optimize]
heights_mm = {{ min = -6.0, max = 20.0, step = 0.1 }}
"""


def bspline(n):
    # A flat start at -10 mm (the paraboloid's control points would not do: the source
    # clearance check bounds a B-spline by its control heights' hull, and a paraboloid's
    # rim heights then reach the source).
    return f"""
[reflector]
family = "bspline"
grid = [{n}, {n}]
heights_mm = -10.0

[reflector.optimize]
heights_mm = {{ min = -20.0, max = 0.0, step = 0.1 }}
"""


FAMILIES = {
    "paraboloid": paraboloid,
    "profile8": lambda: profile(8),
    "profile16": lambda: profile(16),
    "bspline6": lambda: bspline(6),
    "bspline10": lambda: bspline(10),
}


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for target, file in TARGETS.items():
        for family, body in FAMILIES.items():
            title = f"{family} against {target} ({file})"
            path = os.path.join(out, f"{target}_{family}.toml")
            rel = os.path.relpath(os.path.join(CORPUS, file), out)
            # A profile: room for CMA-ES's run and its polish at 16 heights (about 1600
            # candidates) and another run after it.
            max_evals = {"paraboloid": 600, "profile8": 3000, "profile16": 3000}.get(family, 1500)
            text = HEADER.format(title=title) + body() + TAIL.format(target=rel, max_evals=max_evals)
            with open(path, "w") as f:
                f.write(text)
            print(path)


if __name__ == "__main__":
    main()
