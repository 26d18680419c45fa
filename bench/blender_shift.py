#!/usr/bin/python3
"""Sub-pixel geometry of two renders of one view (issue #13's comparison with Cycles): a least-squares
fit of OURS - CYCLES (RGB mean per pixel) on CYCLES' image gradient, as an offset (px) and a scale
about the image centre (per px from it) in x and y, with 1-sigma errors. Needs NumPy (Debian's
python3-numpy, which bench/blender_compare.sh installs).

  /usr/bin/python3 bench/blender_shift.py OURS.exr CYCLES.exr
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rb_regions import read_exr  # noqa: E402


def grey(path):
    w, h, c = read_exr(path)
    return (np.array(c['R']) + np.array(c['G']) + np.array(c['B'])).reshape(h, w) / 3.0


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    ours, cycles = grey(argv[1]), grey(argv[2])
    h, w = cycles.shape
    gx, gy = np.zeros_like(cycles), np.zeros_like(cycles)
    gx[:, 1:-1] = (cycles[:, 2:] - cycles[:, :-2]) / 2  # central differences
    gy[1:-1, :] = (cycles[2:, :] - cycles[:-2, :]) / 2
    x, y = np.meshgrid(np.arange(w) + 0.5 - w / 2, np.arange(h) + 0.5 - h / 2)
    inner = np.zeros_like(cycles, bool)
    inner[2:-2, 2:-2] = True
    # ours(p) = cycles(p + d(p)), d = (a_x + s_x x, a_y + s_y y): to first order ours - cycles = grad . d
    a = np.stack([gx[inner], gy[inner], (x * gx)[inner], (y * gy)[inner]], 1)
    b = (ours - cycles)[inner]
    fit, *_ = np.linalg.lstsq(a, b, rcond=None)
    residual = b - a @ fit
    sigma = np.sqrt(np.diag(residual @ residual / (len(b) - 4) * np.linalg.inv(a.T @ a)))
    for name, value, error in zip(('offset x (px)', 'offset y (px)', 'scale x (/px)', 'scale y (/px)'), fit, sigma):
        print(f'{name}: {value:+.2e} +- {error:.1e}')


if __name__ == '__main__':
    main(sys.argv)
