#!/usr/bin/python3
"""Writes the ray files FIRD's ray file tests read: an independent writer (the standard library
only, no FIRD code), with its own sampling of a Lambertian disk, and broken files whose
faults it places itself. Usage: write_ray_files.py OUT_DIR. It also writes
OUT_DIR/manifest.json: the byte offsets (CSV: lines) where it put each fault, the rays and
flux it wrote.

TM-25-13 layout as written here (little-endian): the file header block (256 bytes: "TM25",
version 2013, creation method, luminous flux lm, radiant flux W, ray count (u64), date (28
bytes), start position, spectral data identifier, single, minimum and maximum wavelength,
spectral tables, additional items, additional text bytes, 168 reserved), 8 known-data
flags (i32), 9 description fields of 1000 UTF-32LE code points, the spectral tables (a
point count, then (wavelength, value) pairs) padded to a multiple of 32 bytes, then per ray
x, y, z, kx, ky, kz and the flagged columns as float32."""
import json
import math
import os
import struct
import sys

import random

FIXED = 256 + 32 + 9 * 4000


def tm25_bytes(rays, radiant=None, luminous=None, phi_v=0.0, phi=0.0, spectrum=True,
               pad=True, phi_v_big_endian=False, name="FIRD test disk", count=None):
    """rays: (N, 6) float array; radiant, luminous: per-ray columns or None."""
    n = len(rays) if count is None else count
    head = bytearray()
    head += b"TM25" + struct.pack("<ii", 2013, 0)
    head += struct.pack(">f" if phi_v_big_endian else "<f", phi_v)
    head += struct.pack("<fQ", phi, n)
    head += b"2026-12-03T12:00:00Z".ljust(28, b"\0")
    head += struct.pack("<ii", 0, 3 if spectrum else 0)
    head += struct.pack("<fff", float("nan"), 400.0 if spectrum else float("nan"),
                        700.0 if spectrum else float("nan"))
    head += struct.pack("<iii", 1 if spectrum else 0, 0, 0)
    head += bytes(168)
    assert len(head) == 256
    flags = [1, 1, int(radiant is not None), 0, int(luminous is not None), 0, 0, 0]
    head += struct.pack("<8i", *flags)
    for k in range(9):
        text = (name if k == 0 else "FIRD tests" if k == 1 else "").encode("utf-32-le")
        head += text.ljust(4000, b"\0")
    assert len(head) == FIXED
    if spectrum:
        points = 51
        table = struct.pack("<i", points)
        for i in range(points):
            table += struct.pack("<ff", 400.0 + 6.0 * i, 100.0 * math.exp(-((i - 25) / 10) ** 2))
        head += table
        if pad:
            head += bytes((32 - len(table) % 32) % 32)
    records = []
    for i, r in enumerate(rays):
        row = list(r)
        if radiant is not None:
            row.append(radiant[i])
        if luminous is not None:
            row.append(luminous[i])
        records.append(row)
    return bytes(head), records


def f32(x):
    """x rounded to float32, as a Python float."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def record_bytes(records):
    return b"".join(struct.pack("<%df" % len(r), *r) for r in records)


def write_tm25(path, head, records):
    with open(path, "wb") as f:
        f.write(head)
        f.write(record_bytes(records))


def lambertian_disk(n, radius_mm, rng):
    """Uniform over a disk of the given radius in z = 0, Lambertian about +z (sin^2 of the
    angle from +z uniform); values rounded to float32."""
    out = []
    for _ in range(n):
        r = radius_mm * math.sqrt(rng.random())
        phi = 2 * math.pi * rng.random()
        s2 = rng.random()
        psi = 2 * math.pi * rng.random()
        st, ct = math.sqrt(s2), math.sqrt(1 - s2)
        out.append([f32(v) for v in (r * math.cos(phi), r * math.sin(phi), 0.0,
                                     st * math.cos(psi), st * math.sin(psi), ct)])
    return out


def write_npy(path, rows, code):
    """A version 1.0 .npy file of the rows (all of one length), '<f4' or '<f8'; returns
    the byte offset of its data."""
    header = "{'descr': '%s', 'fortran_order': False, 'shape': (%d, %d), }" % (
        code, len(rows), len(rows[0]))
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    fmt = "<%d%s" % (len(rows[0]), "f" if code == "<f4" else "d")
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        for r in rows:
            f.write(struct.pack(fmt, *r))
    return 10 + len(header)


def main(out):
    os.makedirs(out, exist_ok=True)
    rng = random.Random(20261203)
    manifest = {}

    # A Lambertian disk (radius 1.5 mm, emitting along +z), 200 000 rays: radiant flux per
    # ray, the luminous flux (100 lm) in the header alone.
    disk = lambertian_disk(200000, 1.5, rng)
    head, rec = tm25_bytes(disk, radiant=[1e-6] * len(disk), phi_v=100.0, phi=0.2)
    write_tm25(os.path.join(out, "disk.tm25ray"), head, rec)
    manifest["disk"] = {"rays": len(disk), "flux_lm": 100.0, "ray_offset": len(head)}

    # The same disk's first 3000 rays as npy (float64, N x 6; float32, N x 7 with 0.01 lm
    # each), CSV (columns in another order, with flux) and TM-25 (luminous flux per ray).
    part = disk[:3000]
    write_npy(os.path.join(out, "part.npy"), part, "<f8")
    write_npy(os.path.join(out, "part_flux.npy"), [r + [0.01] for r in part], "<f4")
    with open(os.path.join(out, "part.csv"), "w") as f:
        f.write("flux, dz, dy, dx, z, y, x\n")
        for r in part:
            f.write("0.01, {!r}, {!r}, {!r}, {!r}, {!r}, {!r}\n".format(
                r[5], r[4], r[3], r[2], r[1], r[0]))
    head, rec = tm25_bytes(part, luminous=[0.01] * 3000, spectrum=False)
    write_tm25(os.path.join(out, "part.tm25ray"), head, rec)
    manifest["part"] = {"rays": 3000, "flux_lm": 3000 * f32(0.01)}

    # Unequal luminous flux per ray (1 lm or 3 lm, at random), the header's luminous flux a
    # NaN written big-endian, and the spectral table's padding left out.
    pts = lambertian_disk(20000, 1.0, rng)
    weights = [1.0 if rng.random() < 0.5 else 3.0 for _ in pts]
    head, rec = tm25_bytes(pts, luminous=weights, phi_v=float("nan"), phi_v_big_endian=True,
                           pad=False)
    write_tm25(os.path.join(out, "weighted.tm25ray"), head, rec)
    manifest["weighted"] = {"rays": 20000, "flux_lm": sum(weights),
                            "heavy_weight": sum(w for w in weights if w == 3.0),
                            "ray_offset": len(head)}
    with open(os.path.join(out, "weighted_heavy.txt"), "w") as f:
        f.write("".join("1" if w == 3.0 else "0" for w in weights))

    # Radiant flux alone, no luminous flux anywhere: the scene must give flux_lm.
    head, rec = tm25_bytes(pts[:100], radiant=[1e-3] * 100, phi_v=0.0, phi=0.1)
    write_tm25(os.path.join(out, "radiant_only.tm25ray"), head, rec)

    # Refusals, each at a byte the writer chose.
    head, rec = tm25_bytes(pts[:50], luminous=[1.0] * 50, spectrum=False)
    data = head + record_bytes(rec)
    with open(os.path.join(out, "short.tm25ray"), "wb") as f:
        f.write(data[:1000])  # cut inside the description fields
    manifest["short"] = {"byte": 1000}
    with open(os.path.join(out, "bad_tag.tm25ray"), "wb") as f:
        f.write(b"TM26" + data[4:])
    manifest["bad_tag"] = {"byte": 0}
    head2, rec2 = tm25_bytes(pts[:50], luminous=[1.0] * 50, spectrum=False, count=51)
    with open(os.path.join(out, "size_mismatch.tm25ray"), "wb") as f:
        f.write(head2 + record_bytes(rec2))
    manifest["size_mismatch"] = {"byte": len(head2)}
    bad = [list(r) for r in rec]
    bad[7][3] = float("nan")  # ray 7's kx
    write_tm25(os.path.join(out, "nan_direction.tm25ray"), head, bad)
    manifest["nan_direction"] = {"byte": len(head) + 7 * 7 * 4 + 3 * 4}
    bad = [list(r) for r in rec]
    bad[5][6] = -1.0  # ray 5's flux
    write_tm25(os.path.join(out, "negative_flux.tm25ray"), head, bad)
    manifest["negative_flux"] = {"byte": len(head) + 5 * 7 * 4 + 6 * 4}
    zero = [list(r) for r in part[:10]]
    zero[3][3:6] = [0.0, 0.0, 0.0]  # ray 3's direction
    offset = write_npy(os.path.join(out, "zero_direction.npy"), zero, "<f4")
    manifest["zero_direction"] = {"byte": offset + 3 * 6 * 4 + 3 * 4}
    with open(os.path.join(out, "nan_direction.csv"), "w") as f:
        f.write("x,y,z,dx,dy,dz\n")
        for i, r in enumerate(part[:10]):
            dx = "nan" if i == 4 else repr(r[3])
            f.write("{!r},{!r},{!r},{},{!r},{!r}\n".format(r[0], r[1], r[2], dx, r[4], r[5]))
    manifest["nan_direction_csv"] = {"line": 6}  # the header, rays 0 to 3, then ray 4

    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1])
