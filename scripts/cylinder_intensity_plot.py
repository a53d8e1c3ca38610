#!/usr/bin/python3
"""A bare Lambertian cylinder's intensity against the angle to its axis, from far fields
written by `fird trace scenes/test/bare_cylinder.toml --out DIR` (DIR/farfield.npy), beside
the analytic I = (flux / pi^2) sin(theta): a cylinder's projected area goes as the sine of
the angle to its axis (docs/sources.md, "One definition of the emission").

    scripts/cylinder_intensity_plot.py OUT.png LABEL=DIR/farfield.npy [LABEL=...]

Prints, per far field, its flux and the largest gap between its intensity and the analytic
one over 4-degree bands about the axis (x, the scene's; each band's analytic intensity is
averaged over the same cells as the measured one), and draws the figure with ImageMagick's
`convert`. Python's standard library only."""
import array
import ast
import math
import struct
import subprocess
import sys

BANDS = 45  # 4 degrees each
COLOURS = ['royalblue', 'darkorange', 'seagreen', 'crimson']
FONT = '/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf'


def load_npy(path):
    data = open(path, 'rb').read()
    if data[:6] != b'\x93NUMPY' or data[6] != 1:
        sys.exit(f'{path}: not a version 1 .npy file')
    header_len = struct.unpack('<H', data[8:10])[0]
    header = ast.literal_eval(data[10:10 + header_len].decode())
    if header.get('fortran_order') or header.get('descr') not in ('<f8', '<f4'):
        sys.exit(f'{path}: not a C-ordered float32 or float64 array')
    values = array.array({'<f8': 'd', '<f4': 'f'}[header['descr']])
    values.frombytes(data[10 + header_len:])
    return header['shape'], values


def intensity_by_band(path):
    """Per band of the angle to x: the mean intensity (cd) and the mean of sin(theta) over
    the same cells (the analytic intensity's shape); and the far field's flux (lm). Cells
    are assigned to bands by their centres; a band's solid angle is the sum of its cells'
    (trace.comp's far_field_cell: row 0 at the zenith, column 0 at azimuth -pi)."""
    shape, lm = load_npy(path)
    rows, cols = shape[-2], shape[-1]
    band_lm, band_sr, band_sin = [0.0] * BANDS, [0.0] * BANDS, [0.0] * BANDS
    for row in range(rows):
        top = math.pi / 2 - row * math.pi / rows
        bottom = top - math.pi / rows
        elevation = 0.5 * (top + bottom)
        cell_sr = (2 * math.pi / cols) * (math.sin(top) - math.sin(bottom))
        for col in range(cols):
            azimuth = (col + 0.5) * 2 * math.pi / cols - math.pi
            along_x = math.cos(elevation) * math.cos(azimuth)
            theta = math.acos(max(-1.0, min(1.0, along_x)))
            band = min(BANDS - 1, int(theta / math.pi * BANDS))
            band_lm[band] += lm[row * cols + col]
            band_sr[band] += cell_sr
            band_sin[band] += math.sin(theta) * cell_sr
    if min(band_sr) <= 0.0:
        sys.exit(f'{path}: a 4-degree band holds no cell centre (far field too coarse)')
    return ([l / s for l, s in zip(band_lm, band_sr)],
            [q / s for q, s in zip(band_sin, band_sr)], math.fsum(lm))


def main():
    if len(sys.argv) < 3 or any('=' not in a for a in sys.argv[2:]):
        sys.exit(__doc__)
    out = sys.argv[1]
    series = []
    for arg in sys.argv[2:]:
        label, path = arg.split('=', 1)
        profile, mean_sin, flux = intensity_by_band(path)
        series.append((label, profile, flux))
        gap = max(abs(v - flux / math.pi ** 2 * q) for v, q in zip(profile, mean_sin))
        print(f'{label}: {flux:.3f} lm, peak {flux / math.pi ** 2:.2f} cd, '
              f'largest gap to the sine law {gap:.2f} cd')
    flux = series[0][2]
    peak = flux / math.pi ** 2
    w, h, left, right, top, bottom = 650, 420, 70, 30, 40, 60
    top_cd = 20 * math.ceil(peak * 1.15 / 20)

    def x(deg):
        return left + (w - left - right) * deg / 180.0

    def y(cd):
        return h - bottom - (h - top - bottom) * cd / top_cd

    cmd = ['convert', '-size', f'{w}x{h}', 'xc:white', '-stroke', 'gray80', '-strokewidth', '1']
    for cd in range(0, int(top_cd) + 1, 20):
        cmd += ['-draw', f'line {left},{y(cd):.1f} {w - right},{y(cd):.1f}']
    for deg in range(0, 181, 30):
        cmd += ['-draw', f'line {x(deg):.1f},{top} {x(deg):.1f},{h - bottom}']
    curve = ' '.join(f'{x(d / 2):.1f},{y(peak * math.sin(math.radians(d / 2))):.1f}'
                     for d in range(0, 361))
    cmd += ['-fill', 'none', '-stroke', 'black', '-strokewidth', '2', '-draw', f'polyline {curve}']
    for k, (label, profile, _) in enumerate(series):
        colour, shift = COLOURS[k % len(COLOURS)], 3.0 * (k - (len(series) - 1) / 2)
        for b, v in enumerate(profile):
            cx, cy = x((b + 0.5) * 180 / BANDS) + shift, y(v)
            cmd += ['-fill', colour, '-stroke', colour, '-strokewidth', '1',
                    '-draw', f'circle {cx:.1f},{cy:.1f} {cx + 3:.1f},{cy:.1f}']
    cmd += ['-font', FONT, '-stroke', 'none', '-fill', 'black', '-pointsize', '13']
    for cd in range(0, int(top_cd) + 1, 20):
        cmd += ['-annotate', f'+{left - 32}+{y(cd) + 4:.0f}', str(cd)]
    for deg in range(0, 181, 30):
        cmd += ['-annotate', f'+{x(deg) - 8:.0f}+{h - bottom + 18}', f'{deg}°']
    cmd += ['-annotate', f'+{w / 2 - 120:.0f}+{h - 15}', "angle to the cylinder's axis (degrees)"]
    cmd += ['-annotate', f'+8+{top - 12}', 'cd']
    cmd += ['-pointsize', '14', '-annotate', f'+{left}+22',
            'A bare Lambertian cylinder: intensity against the angle to its axis']
    legend = [('black', f'analytic: ({flux:.0f} lm / π²) sin θ')]
    legend += [(COLOURS[k % len(COLOURS)], label) for k, (label, _, _) in enumerate(series)]
    for k, (colour, label) in enumerate(legend):
        cmd += ['-fill', colour, '-annotate', f'+{left + 175}+{top + 250 + 18 * k}', '● ' + label]
    subprocess.run(cmd + [out], check=True)


if __name__ == '__main__':
    main()
