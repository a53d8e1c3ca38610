#!/usr/bin/python3
"""Writes the files of the ray file speed benchmark (issue 25 item 9, docs/benchmarks.md):
two TM-25 ray files sampled here, with the standard library alone (the independent writer
of tests/io/write_ray_files.py gives the header), and the scenes that trace them beside the
analytic emitters of the same light, all on the LED die's paraboloid at every ray of the
file:

  cylinder.toml / rayfile_cylinder.toml   FIRD's analytic cylinder along x, 1 mm long and
                                           0.3 mm in radius, and a file of rays drawn from it
  disk.toml / rayfile_disk.toml           a Lambertian disk of radius 0.5 mm facing down, and
                                           a file of rays drawn from that disk

Each pair emits the same light, so a side-by-side time of its two scenes is the cost of
reading the rays from a file instead of sampling them. Usage: ray_file_bench.py OUT_DIR
[RAYS] (default 5 000 000 rays per file, 140 MB each)."""
import array
import math
import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "io"))
from write_ray_files import tm25_bytes  # noqa: E402

FLUX_LM = 120.0
CYLINDER = {"length_mm": 1.0, "radius_mm": 0.3}
DISK_RADIUS_MM = 0.5


def cosine_about(n, t, b, rng):
    """A Lambertian direction about unit n in the frame (t, b, n)."""
    s2 = rng.random()
    psi = 2 * math.pi * rng.random()
    st, ct = math.sqrt(s2), math.sqrt(1 - s2)
    return [st * math.cos(psi) * t[k] + st * math.sin(psi) * b[k] + ct * n[k] for k in range(3)]


def cylinder_ray(rng):
    """Uniform over the lateral surface of a cylinder along x, caps dark, Lambertian about the
    outward normal."""
    x = (rng.random() - 0.5) * CYLINDER["length_mm"]
    phi = 2 * math.pi * rng.random()
    n = [0.0, math.cos(phi), math.sin(phi)]
    t = [1.0, 0.0, 0.0]
    b = [0.0, -math.sin(phi), math.cos(phi)]  # t x n
    r = CYLINDER["radius_mm"]
    return [x, r * n[1], r * n[2]] + cosine_about(n, t, b, rng)


def disk_ray(rng):
    """Uniform over a disk in z = 0, Lambertian about +z (the file's axes; the scene turns
    +z down)."""
    rho = DISK_RADIUS_MM * math.sqrt(rng.random())
    phi = 2 * math.pi * rng.random()
    return [rho * math.cos(phi), rho * math.sin(phi), 0.0] + cosine_about(
        [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], rng)


def write_file(path, rays, draw, rng):
    head, _ = tm25_bytes([], phi_v=FLUX_LM, count=rays, spectrum=False,
                         name="FIRD ray file benchmark")
    with open(path, "wb") as f:
        f.write(head)
        block = 1 << 16
        for first in range(0, rays, block):
            values = array.array("f")
            for _ in range(min(block, rays - first)):
                values.extend(draw(rng))
            if sys.byteorder != "little":
                values.byteswap()
            f.write(values.tobytes())


SCENE = """# The LED die's paraboloid (scenes/led_die.toml) with {what}: issue 25 item 9's benchmark
# (scripts/ray_file_bench.py, docs/benchmarks.md).
name = "{name}"

[source]
{source}
center_mm = [0.0, 0.0, 0.0]
flux_lm = {flux}

[holder]
min_mm = [-30.0, -20.0, -20.0]
max_mm = [30.0, 20.0, 0.0]

[reflector]
family = "paraboloid"
fx = 12.0
fy = 8.0
z0 = -11.0
cx = 0.0
cy = 0.0

[reflector.optimize]
fx = {{ min = 6.0, max = 16.0, step = 0.5 }}

[trace]
rays = {rays}
seed = 1
max_bounces = 1
bounce_policy = "paper"
sampler = "stratified"
hit_mode = "refined"
heightfield = [1200, 800]
farfield = [360, 180]
"""


def main(out, rays):
    os.makedirs(out, exist_ok=True)
    rng = random.Random(20261204)
    write_file(os.path.join(out, "cylinder.tm25ray"), rays, cylinder_ray, rng)
    write_file(os.path.join(out, "disk.tm25ray"), rays, disk_ray, rng)
    sources = {
        "cylinder": ("a cylinder 1 mm long, 0.3 mm in radius", 'type = "cylinder"\naxis = [1.0, 0.0, 0.0]\n'
                     'length_mm = {length_mm}\nradius_mm = {radius_mm}\nemittance = "cosine"'
                     .format(**CYLINDER)),
        "rayfile_cylinder": ("a ray file drawn from that cylinder",
                             'type = "rayfile"\nfile = "cylinder.tm25ray"'),
        "disk": ("a Lambertian disk facing down",
                 'type = "disk"\nnormal = [0.0, 0.0, -1.0]\nradius_mm = {}'.format(
                     DISK_RADIUS_MM)),
        "rayfile_disk": ("a ray file drawn from that disk",
                         'type = "rayfile"\nfile = "disk.tm25ray"\nnormal = [0.0, 0.0, -1.0]'),
    }
    for name, (what, source) in sources.items():
        with open(os.path.join(out, name + ".toml"), "w") as f:
            f.write(SCENE.format(what=what, name=name, source=source, flux=FLUX_LM, rays=rays))


if __name__ == "__main__":
    main(sys.argv[1], int(float(sys.argv[2])) if len(sys.argv) > 2 else 5000000)
