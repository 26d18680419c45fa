#!/usr/bin/env python3
"""Compares one bundlepath render of the smooth-edges scene with its Cycles reference
(bench/smooth_edges.sh): are smooth rims and silhouettes black where Cycles shades them?
Runs in the peers' venv (numpy, OpenEXR).

  smooth_edges_compare.py OURS.exr CYCLES1.exr [CYCLES2.exr] --label NAME [--header]
                          [--png OUT.png] [--json OUT.json]

CYCLES1, CYCLES2: Cycles at two seeds (same spp); the reference is their mean and their difference
its noise. Values are Rec. 709 luminance. One Markdown row (--header: the table's head first):

* mean ratio: ours' image mean over Cycles';
* black blocks: 4x4-pixel blocks where Cycles' block mean is above 5 % of its image mean and ours
  is below a quarter of Cycles' (a surface Cycles draws that ours leaves black), of the blocks
  above 5 %; "Cycles' own" is the same count between the two Cycles seeds (0 expected: what noise
  alone gives);
* black pixels: the same test per pixel (Cycles' pixel above 5 % of its image mean, ours below a
  quarter of it), and Cycles' own count between its seeds (noise alone: a few);
* worst region: the largest |ours / Cycles - 1| of the mean luminance over the regions of an 8x8
  grid (pixel (x, y) in region (8x / width, 8y / height), as `render --regions 8` and
  bench/peers/compare.py cut images), over regions above 1 % of the image mean; its region
  (column, row), and its z: the error over the standard error of both sides (ours from the EXR's
  per-pixel `stderr` layer, pixels taken independent; Cycles' from its seed pair), |z| > 4 being
  beyond noise;
* regions > 5 %: how many regions are off by more than 5 % (and over 4 sigma).

--png: ours | Cycles | per 4x4 block (ours - Cycles) / Cycles (red: ours brighter, blue: darker,
full colour at 50 %; yellow: a black block), side by side, sRGB (no Pillow needed).
"""
import argparse
import json

import numpy as np
import OpenEXR

from pbr_room_compare import png_write  # bench/: numpy-only PNG writer

Y = np.array([0.2126, 0.7152, 0.0722])
BLOCK = 4
GRID = 8
LIT = 0.05          # a block counts when Cycles' mean is above this fraction of Cycles' image mean
BLACK = 0.25        # ... and is black when ours is below this fraction of Cycles'
REGION_LIT = 0.01
Z_NOISE = 4.0


def read(path, layer="RGB"):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        for name in ((layer, "RGBA") if layer == "RGB" else (layer,)):
            if name in ch:
                return np.asarray(ch[name].pixels, dtype=np.float64)[..., :3]
        names = [f"{layer}.{c}" for c in "RGB"] if layer != "RGB" else list("RGB")
        if all(n in ch for n in names):
            return np.stack([np.asarray(ch[n].pixels, dtype=np.float64) for n in names], -1)
    return None


def blocks(y, b=BLOCK):
    h, w = (y.shape[0] // b) * b, (y.shape[1] // b) * b
    return y[:h, :w].reshape(h // b, b, w // b, b).mean(axis=(1, 3))


def regions(y, n=GRID, reduce=np.mean):
    h, w = y.shape
    rows, cols = np.arange(h) * n // h, np.arange(w) * n // w
    return np.array([[reduce(y[rows == r][:, cols == c]) for c in range(n)] for r in range(n)])


def region_sizes(shape, n=GRID):
    h, w = shape
    rows, cols = np.arange(h) * n // h, np.arange(w) * n // w
    return np.outer(np.bincount(rows, minlength=n), np.bincount(cols, minlength=n)).astype(np.float64)


def black_blocks(img, ref, block=BLOCK):
    bi, br = (blocks(img, block), blocks(ref, block)) if block > 1 else (img, ref)
    lit = br > LIT * ref.mean()
    black = lit & (bi < BLACK * br)
    return black, int(lit.sum())


def srgb8(x):
    x = np.clip(x, 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (255.0 * s + 0.5).astype(np.uint8)


def diff_picture(ours, ref, black):
    yo, yr = ours @ Y, ref @ Y
    bo, br = blocks(yo), blocks(yr)
    lit = br > LIT * yr.mean()
    d = np.where(lit, (bo - br) / np.where(br > 0, br, 1.0), 0.0)
    t = np.clip(np.abs(d) / 0.5, 0.0, 1.0)
    grey = 0.35
    pic = np.full(br.shape + (3,), grey)
    pic[..., 0] = np.where(d > 0, grey + (1 - grey) * t, grey * (1 - t))
    pic[..., 1] = grey * (1 - t)
    pic[..., 2] = np.where(d < 0, grey + (1 - grey) * t, grey * (1 - t))
    pic[~lit] = 0.08
    pic[black] = (1.0, 0.9, 0.0)
    pic = np.repeat(np.repeat(pic, BLOCK, axis=0), BLOCK, axis=1)
    out = np.zeros_like(ours)
    out[:pic.shape[0], :pic.shape[1]] = pic
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("ours")
    p.add_argument("cycles", nargs="+")
    p.add_argument("--label", default="")
    p.add_argument("--header", action="store_true")
    p.add_argument("--png")
    p.add_argument("--json")
    a = p.parse_args()
    if len(a.cycles) > 2:
        p.error("one or two Cycles renders")
    ours = read(a.ours)
    cyc = [read(c) for c in a.cycles]
    for c, name in zip(cyc, a.cycles):
        if c.shape != ours.shape:
            raise SystemExit(f"smooth_edges_compare: {name} is {c.shape[1]}x{c.shape[0]}, "
                             f"ours {ours.shape[1]}x{ours.shape[0]}")
    ref = sum(cyc) / len(cyc)
    yo, yr = ours @ Y, ref @ Y
    n = region_sizes(yo.shape)

    black, lit_blocks = black_blocks(yo, yr)
    own_black = black_blocks(cyc[0] @ Y, cyc[1] @ Y)[0].sum() if len(cyc) == 2 else None
    black_px, lit_px = black_blocks(yo, yr, 1)
    own_black_px = black_blocks(cyc[0] @ Y, cyc[1] @ Y, 1)[0].sum() if len(cyc) == 2 else None

    ro, rr = regions(yo), regions(yr)
    keep = rr > REGION_LIT * yr.mean()
    err = np.where(keep, ro / np.where(keep, rr, 1.0) - 1.0, 0.0)
    stderr = read(a.ours, "stderr")
    var_o = regions((stderr ** 2) @ (Y ** 2), reduce=np.sum) / n ** 2 if stderr is not None else np.zeros_like(ro)
    if len(cyc) == 2:  # a render's region mean: sum (x1 - x2)^2 / 2 / n^2; their mean: half that
        var_r = regions((cyc[0] @ Y - cyc[1] @ Y) ** 2, reduce=np.sum) / 2 / n ** 2 / 2
    else:
        var_r = np.zeros_like(rr)
    se = np.sqrt(var_o + var_r)
    z = np.where(se > 0, (ro - rr) / np.where(se > 0, se, 1.0), np.inf)
    worst = np.unravel_index(np.argmax(np.abs(err)), err.shape)
    over = keep & (np.abs(err) > 0.05)
    over_sig = over & (np.abs(z) > Z_NOISE)
    rel_se_r = np.sqrt(var_r[worst]) / rr[worst]

    result = {
        "label": a.label, "mean_ratio": float(yo.mean() / yr.mean()),
        "black_blocks": int(black.sum()), "lit_blocks": lit_blocks,
        "cycles_own_black_blocks": None if own_black is None else int(own_black),
        "black_block_cells": [[int(r), int(c)] for r, c in zip(*np.nonzero(black))],
        "black_pixels": int(black_px.sum()), "lit_pixels": lit_px,
        "cycles_own_black_pixels": None if own_black_px is None else int(own_black_px),
        "worst_region": {"column": int(worst[1]), "row": int(worst[0]), "error": float(err[worst]),
                         "z": float(z[worst]), "cycles_rel_stderr": float(rel_se_r)},
        "regions_over_5pct": int(over.sum()), "regions_over_5pct_and_4_sigma": int(over_sig.sum()),
        "region_errors": err.tolist(),
    }
    if a.header:
        print("| camera | mean ratio (ours / Cycles) | black 4x4 blocks (of lit) | Cycles' own | black pixels "
              "| Cycles' own | worst 8x8 region: error (col, row) | its z | regions > 5 % (and > 4 sigma) |")
        print("|---|---|---|---|---|---|---|---|---|")
    own = "-" if own_black is None else str(own_black)
    own_px = "-" if own_black_px is None else str(own_black_px)
    print("| %s | %.4f | %d (of %d) | %s | %d | %s | %+.1f %% (%d, %d) | %+.1f | %d (%d) |" % (
        a.label, result["mean_ratio"], black.sum(), lit_blocks, own, black_px.sum(), own_px, 100 * err[worst],
        worst[1], worst[0], z[worst], over.sum(), over_sig.sum()))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)
    if a.png:
        # one exposure for both: Cycles' 99th luminance percentile to 0.9
        scale = 0.9 / max(np.percentile(yr, 99), 1e-6)
        pic = np.concatenate([ours * scale, ref * scale, diff_picture(ours, ref, black)], axis=1)
        png_write(a.png, srgb8(pic))


if __name__ == "__main__":
    main()
