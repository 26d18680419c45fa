#!/usr/bin/env python3
"""Relative errors of renders against a reference over small boxes of pixels (luminance), for
bench/patch_refine.sh: per box size, the image mean's error, the worst box, how many boxes are off by
more than 5 % and 10 %, the RMS over boxes, and the error of the boxes at --at X,Y (pixel corners).
Boxes darker than 5 % of the reference's mean are left out (their relative error is noise).

  box_errors.py REFERENCE.exr IMAGE.exr... [--sizes 4,8,16] [--at X,Y]

Needs numpy and OpenEXR (the peers' venv: bench/peers/setup.sh).
"""
import argparse

import numpy as np
import OpenEXR


def luminance(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        px = np.asarray(ch["RGBA" if "RGBA" in ch else "RGB"].pixels, dtype=np.float64)[..., :3]
    return px @ np.array([0.2126, 0.7152, 0.0722])  # Rec. 709


def boxes(y, b):
    h, w = (y.shape[0] // b) * b, (y.shape[1] // b) * b
    return y[:h, :w].reshape(h // b, b, w // b, b).mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("reference")
    ap.add_argument("images", nargs="+")
    ap.add_argument("--sizes", default="4,8,16")
    ap.add_argument("--at", default=None, help="X,Y: a pixel whose boxes to report")
    a = ap.parse_args()
    ref = luminance(a.reference)
    print("| image | box | image mean | worst box (at px) | over 5 % | over 10 % | RMS | box at " + (a.at or "-") + " |")
    print("|---|---|---|---|---|---|---|---|")
    for path in a.images:
        img = luminance(path)
        for b in (int(s) for s in a.sizes.split(",")):
            r, v = boxes(ref, b), boxes(img, b)
            lit = r > 0.05 * ref.mean()
            e = np.where(lit, v / np.where(lit, r, 1.0) - 1.0, 0.0)
            i = np.unravel_index(np.argmax(np.abs(e)), e.shape)
            at = "-"
            if a.at:
                x, y = (int(c) for c in a.at.split(","))
                at = f"{100 * e[y // b, x // b]:+.1f} %"
            print(f"| {path.split('/')[-1]} | {b}×{b} | {100 * (img.mean() / ref.mean() - 1):+.2f} % | "
                  f"{100 * e[i]:+.1f} % ({i[1] * b}, {i[0] * b}) | {(np.abs(e) > 0.05).sum()} of {lit.sum()} | "
                  f"{(np.abs(e) > 0.10).sum()} | {100 * np.sqrt((e[lit] ** 2).mean()):.2f} % | {at} |")


if __name__ == "__main__":
    main()
