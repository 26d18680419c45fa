#!/usr/bin/env python3
"""Compares one bundlepath render with a Cycles reference (bench/pbr_room.sh): luminance
(Rec. 709 Y) image mean, every BxB block's mean, and one patch (the sunlit floor), each with its
noise, from a second render of each side at another seed.

  pbr_room_compare.py OURS1.exr OURS2.exr CYCLES1.exr CYCLES2.exr --label NAME
                      [--block 8] [--regions 8] [--patch L T R B] [--at X,Y ...] [--png SIDE_BY_SIDE.png]
                      [--json OUT.json]

Each image may be A.exr+B.exr+...: the mean of those renders.
--patch: the patch as fractions of the width and height (left, top, right, bottom).
Differences are (ours1 - Cycles1) / Cycles1. Noise: a block's mean differs between two seeds by
sqrt 2 sigma; per block, sigma^2 of a render's block mean is estimated from its pixels,
sum_p (x1_p - x2_p)^2 / 2 / n^2 (pixels independent: exact for path tracing; for ray bundles, whose
pixels share patches, an underestimate), and sigma of ours - Cycles is sqrt(sigma_ours^2 +
sigma_Cycles^2). A block is "testable" against the 5 % bar when 3 sigma <= 5 % of its Cycles level;
a block "fails" when it is testable and over 5 %; "significant" when over 3 sigma as well.
--at X,Y ...: those BxB blocks (column, row) too, each side's mean over both seeds.
--regions N: the same for the N x N grid of `render --regions N` (the regional error of the
project's standard; noise from the pixels alike).
Needs numpy and OpenEXR (the peers' venv has both); prints Markdown.
"""
import argparse
import json
import struct
import sys
import zlib

import numpy as np
import OpenEXR

Y = np.array([0.2126, 0.7152, 0.0722])


def load(paths):
    """PATH or A.exr+B.exr+...: the mean of those renders (a render of their summed samples)."""
    parts = paths.split("+")
    return sum(load_one(q) for q in parts) / len(parts)


def load_one(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        if "RGBA" in ch or "RGB" in ch:
            px = np.asarray(ch["RGBA" if "RGBA" in ch else "RGB"].pixels, dtype=np.float64)[..., :3]
        else:
            names = [n for n in ("R", "G", "B")]
            px = np.stack([np.asarray(ch[n].pixels, dtype=np.float64) for n in names], axis=-1)
    return px


def lum(px):
    return px @ Y


def blocks(y, b):
    h, w = y.shape
    bh, bw = h // b, w // b
    return y[:bh * b, :bw * b].reshape(bh, b, bw, b).mean(axis=(1, 3))


def block_var(y1, y2, b):
    """Variance of one render's block mean, from the pixel differences of two seeds."""
    d2 = (y1 - y2) ** 2 / 2.0
    h, w = d2.shape
    bh, bw = h // b, w // b
    return d2[:bh * b, :bw * b].reshape(bh, b, bw, b).sum(axis=(1, 3)) / float(b * b) ** 2


def region_index(y, n):
    """Each pixel's row and column in the n x n grid of `render --regions n` (host/image/regions.h)."""
    h, w = y.shape
    return (np.arange(h) * n) // h, (np.arange(w) * n) // w


def region_means(y, n):
    rows, cols = region_index(y, n)
    return np.array([[y[np.ix_(rows == j, cols == i)].mean() for i in range(n)] for j in range(n)])


def region_var(y1, y2, n):
    """Variance of one render's region mean, from the pixel differences of two seeds."""
    d2 = (y1 - y2) ** 2 / 2.0
    rows, cols = region_index(d2, n)
    return np.array([[d2[np.ix_(rows == j, cols == i)].sum() / float((rows == j).sum() * (cols == i).sum()) ** 2
                      for i in range(n)] for j in range(n)])


def png_write(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[j].tobytes() for j in range(h))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def pct(x, d=2):
    return "%+.*f %%" % (d, 100.0 * x)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("ours1")
    p.add_argument("ours2")
    p.add_argument("ref1")
    p.add_argument("ref2")
    p.add_argument("--label", default="ours")
    p.add_argument("--block", type=int, default=8)
    p.add_argument("--regions", type=int, default=8)
    p.add_argument("--patch", type=float, nargs=4)
    p.add_argument("--at", nargs="*", default=[])
    p.add_argument("--png")
    p.add_argument("--json")
    a = p.parse_args()
    o1, o2, c1, c2 = (load(f) for f in (a.ours1, a.ours2, a.ref1, a.ref2))
    yo1, yo2, yc1, yc2 = (lum(x) for x in (o1, o2, c1, c2))
    h, w = yc1.shape
    res = {"label": a.label}

    # image mean
    mo, mc = yo1.mean(), yc1.mean()
    n = yo1.size
    s_mean = np.sqrt(((yo1 - yo2) ** 2).sum() / 2 / n ** 2 + ((yc1 - yc2) ** 2).sum() / 2 / n ** 2) / mc
    res.update(mean_ours=mo, mean_cycles=mc, mean_rel=mo / mc - 1, mean_sigma=s_mean,
               mean_seed_ours=yo2.mean() / yo1.mean() - 1, mean_seed_cycles=yc2.mean() / yc1.mean() - 1)

    # blocks
    b = a.block
    bo, bc = blocks(yo1, b), blocks(yc1, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(bc > 0, bo / bc - 1, np.where(bo > 0, np.inf, 0.0))
        sig = np.sqrt(block_var(yo1, yo2, b) + block_var(yc1, yc2, b)) / bc
        sig_c = np.sqrt(block_var(yc1, yc2, b)) / bc
    sig = np.nan_to_num(sig, nan=np.inf)
    testable = 3 * sig <= 0.05
    over = np.abs(rel) > 0.05
    signif = np.abs(rel) > 3 * sig
    worst = np.unravel_index(np.argmax(np.abs(rel)), rel.shape)
    if testable.any():
        rt = np.where(testable, np.abs(rel), -1)
        worst_t = np.unravel_index(np.argmax(rt), rel.shape)
    else:
        worst_t = None
    res.update(blocks=int(rel.size), blocks_testable=int(testable.sum()),
               worst_block=float(rel[worst]), worst_block_at=[int(worst[1]), int(worst[0])],
               worst_block_sigma=float(sig[worst]),
               worst_testable=float(rel[worst_t]) if worst_t else None,
               worst_testable_at=[int(worst_t[1]), int(worst_t[0])] if worst_t else None,
               worst_testable_sigma=float(sig[worst_t]) if worst_t else None,
               over5=int(over.sum()), over5_testable=int((over & testable).sum()),
               over5_significant=int((over & signif).sum()),
               significant_3sigma=int(signif.sum()),
               rms_rel=float(np.sqrt(np.mean(np.where(np.isfinite(rel), rel, 0) ** 2))),
               rms_sigma=float(np.sqrt(np.mean(np.where(np.isfinite(sig), sig, 0) ** 2))),
               median_sigma_cycles=float(np.median(sig_c[np.isfinite(sig_c)])))

    # the 8 x 8 grid of regions (the project's regional error: `render --regions 8`)
    ro, rc = region_means(yo1, a.regions), region_means(yc1, a.regions)
    rrel = ro / rc - 1
    rsig = np.sqrt(region_var(yo1, yo2, a.regions) + region_var(yc1, yc2, a.regions)) / rc
    rworst = np.unravel_index(np.argmax(np.abs(rrel)), rrel.shape)
    res.update(regions=a.regions, region_worst=float(rrel[rworst]), region_worst_at=[int(rworst[1]), int(rworst[0])],
               region_worst_sigma=float(rsig[rworst]), region_over5=int((np.abs(rrel) > 0.05).sum()),
               region_over5_significant=int(((np.abs(rrel) > 0.05) & (np.abs(rrel) > 3 * rsig)).sum()),
               region_median_sigma=float(np.median(rsig)))

    # patch
    if a.patch:
        l, t, r, btm = a.patch
        x0, x1, y0, y1 = int(round(l * w)), int(round(r * w)), int(round(t * h)), int(round(btm * h))
        po, pc = yo1[y0:y1, x0:x1], yc1[y0:y1, x0:x1]
        m = po.size
        ps = np.sqrt(((po - yo2[y0:y1, x0:x1]) ** 2).sum() / 2 / m ** 2 +
                     ((pc - yc2[y0:y1, x0:x1]) ** 2).sum() / 2 / m ** 2) / pc.mean()
        res.update(patch_px=[x0, y0, x1, y1], patch_ours=po.mean(), patch_cycles=pc.mean(),
                   patch_rel=po.mean() / pc.mean() - 1, patch_sigma=ps)

    # Markdown
    print("### %s against Cycles\n" % a.label)
    print("| measure | %s | Cycles | difference | 1 sigma (noise of both) | bar |" % a.label)
    print("|---|---|---|---|---|---|")
    print("| image mean (Y) | %.5g | %.5g | %s | %.2f %% | 2 %% |" % (mo, mc, pct(res["mean_rel"]), 100 * s_mean))
    if a.patch:
        print("| sunlit floor patch (Y), px %s | %.5g | %.5g | %s | %.2f %% | 3 %% |" % (
            res["patch_px"], res["patch_ours"], res["patch_cycles"], pct(res["patch_rel"]), 100 * res["patch_sigma"]))
    print()
    print("%dx%d blocks: %d; testable (3 sigma <= 5 %%): %d. Worst block: %s at (%d, %d) (sigma %.1f %%)%s. "
          "Blocks over 5 %%: %d, of them testable: %d, over 5 %% and over 3 sigma: %d; blocks over 3 sigma: %d. "
          "RMS of the block differences %.2f %%, of their noise %.2f %%; Cycles' own block noise (median sigma) "
          "%.2f %%.\n" % (
              b, b, res["blocks"], res["blocks_testable"], pct(res["worst_block"]), worst[1], worst[0],
              100 * res["worst_block_sigma"],
              ("; worst testable block: %s at (%d, %d) (sigma %.1f %%)" % (
                  pct(res["worst_testable"]), worst_t[1], worst_t[0], 100 * res["worst_testable_sigma"]))
              if worst_t else "", res["over5"], res["over5_testable"], res["over5_significant"],
              res["significant_3sigma"], 100 * res["rms_rel"], 100 * res["rms_sigma"],
              100 * res["median_sigma_cycles"]))
    print("%dx%d grid of regions (`render --regions %d`): worst region %s at (%d, %d) (sigma %.2f %%); regions over "
          "5 %%: %d, of them over 3 sigma: %d; median sigma %.2f %%.\n" % (
              a.regions, a.regions, a.regions, pct(res["region_worst"]), rworst[1], rworst[0],
              100 * res["region_worst_sigma"], res["region_over5"], res["region_over5_significant"],
              100 * res["region_median_sigma"]))
    if a.at:
        bo2, bc2 = blocks(yo2, b), blocks(yc2, b)
        print("| block (column, row) | %s, seeds 1 and 2 | Cycles, seeds 1 and 2 | difference of the means |" % a.label)
        print("|---|---|---|---|")
        for at in a.at:
            i, j = (int(v) for v in at.split(","))
            mo_, mc_ = (bo[j, i] + bo2[j, i]) / 2, (bc[j, i] + bc2[j, i]) / 2
            print("| (%d, %d) | %.4g, %.4g | %.4g, %.4g | %s |" % (i, j, bo[j, i], bo2[j, i], bc[j, i], bc2[j, i],
                                                               pct(mo_ / mc_ - 1, 1)))
        print()
    print("Seed 2 against seed 1, image mean: %s %s, Cycles %s.\n" % (
        a.label, pct(res["mean_seed_ours"]), pct(res["mean_seed_cycles"])))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(res, f, indent=1, default=float)

    if a.png:
        k = 0.8 / max(np.percentile(yc1, 99), 1e-9)
        panel_o = (srgb(o1 * k) * 255 + 0.5).astype(np.uint8)
        panel_c = (srgb(c1 * k) * 255 + 0.5).astype(np.uint8)
        diff = np.full((h, w, 3), 40, dtype=np.uint8)
        bh, bw = rel.shape
        for j in range(bh):
            for i in range(bw):
                r = rel[j, i]
                s = min(1.0, abs(r) / 0.10) if np.isfinite(r) else 1.0
                col = (255 * s, 255 * (1 - s) * 0.2 + 40 * (1 - s), 40 * (1 - s)) if r > 0 else \
                    (40 * (1 - s), 255 * (1 - s) * 0.2 + 40 * (1 - s), 255 * s)
                if not testable[j, i]:
                    col = tuple(0.5 * c + 40 for c in col)
                diff[j * b:(j + 1) * b, i * b:(i + 1) * b] = np.array(col, dtype=np.float64).clip(0, 255)
                if over[j, i] and testable[j, i] and signif[j, i]:  # a white dot: fails the bar
                    diff[j * b + b // 2 - 1:j * b + b // 2 + 1, i * b + b // 2 - 1:i * b + b // 2 + 1] = 255
        if a.patch:
            x0, y0, x1, y1 = res["patch_px"]
            for panel in (panel_o, panel_c):
                panel[y0, x0:x1] = panel[y1 - 1, x0:x1] = (0, 255, 0)
                panel[y0:y1, x0] = panel[y0:y1, x1 - 1] = (0, 255, 0)
        gap = np.full((h, 4, 3), 255, dtype=np.uint8)
        png_write(a.png, np.concatenate([panel_o, gap, panel_c, gap, diff], axis=1))


if __name__ == "__main__":
    sys.exit(main())
