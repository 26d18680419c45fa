#!/usr/bin/env python3
"""An image's error against a reference, split into variance, bias and the reference's own noise, and
judged by 8x8-pixel blocks. Runs in the peers' venv (numpy, OpenEXR: bench/peers/setup.sh).

  error_split.py REFERENCE.exr --images A1.exr A2.exr [--pt P1.exr P2.exr] [--layer L] [--label NAME]
                 [--header]

A1, A2: one method at two seeds (same options); P1, P2: `--mode pt` at two seeds, whose pair gives the
reference's own noise (relMSE of PT less its variance: PT is unbiased); --layer: the images' layer
(e.g. `raw`, a --denoise render's undenoised image); PT's pair is read undenoised (its `raw` layer
where it has one). Per method, one
Markdown row:
* relMSE of A1 and A2 (bundlepath's metric: mean over pixels and channels of (I-R)^2 / (R^2 + 0.01));
* variance: half the relMSE between A1 and A2 (the reference in the denominator);
* bias^2: the mean relMSE less the variance and the reference's own noise (0 without --pt);
* 8x8-pixel blocks of luminance (Rec. 709), those whose reference mean is at least 5 % of the image's:
  median, 99th percentile and largest relative error, and how many are off by more than 5 %, of A1;
* worst |z| of those blocks: the error over the standard error from A1's own `stderr` layer (per
  pixel and channel; a block's as if its pixels were independent) and the reference's, whose own
  standard error is taken from the PT pair's per-pixel spread (0 without --pt). For a denoised image
  the stderr layer is the raw image's: its z says how far the denoiser moved it beyond that noise.
"""
import argparse

import numpy as np
import OpenEXR

LUM = np.array([0.2126, 0.7152, 0.0722])


def read(path, layer="RGB"):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        for name in (layer, "RGBA") if layer == "RGB" else (layer,):  # a peer's EXR: RGBA
            if name in ch:
                return np.asarray(ch[name].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(ch[f"{layer}.{c}"].pixels, dtype=np.float64) for c in "RGB"], -1)


def rel_mse(a, b, ref):
    return float(np.mean((a - b) ** 2 / (ref ** 2 + 0.01)))


def blocks(x, b=8):
    h, w = (x.shape[0] // b) * b, (x.shape[1] // b) * b
    return x[:h, :w].reshape(h // b, b, w // b, b, *x.shape[2:])


def block_stats(image, ref, stderr, ref_var):
    lum_i, lum_r = image @ LUM, ref @ LUM
    bi, br = blocks(lum_i).mean(axis=(1, 3)), blocks(lum_r).mean(axis=(1, 3))
    lit = br >= 0.05 * lum_r.mean()
    err = np.abs(bi[lit] / br[lit] - 1.0)
    n = 64.0
    var_i = blocks((stderr ** 2) @ (LUM ** 2)).sum(axis=(1, 3)) / n ** 2
    var_r = blocks(ref_var @ (LUM ** 2)).sum(axis=(1, 3)) / n ** 2
    se = np.sqrt(var_i + var_r)[lit]
    z = np.where(se > 0, np.abs(bi[lit] - br[lit]) / np.where(se > 0, se, 1.0), np.nan)
    return (float(np.median(err)), float(np.percentile(err, 99)), float(err.max()), int((err > 0.05).sum()),
            int(lit.sum()), float(np.nanmax(z)) if np.isfinite(z).any() else float("nan"))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("reference")
    p.add_argument("--images", nargs=2, required=True)
    p.add_argument("--pt", nargs=2)
    p.add_argument("--layer", default="RGB")
    p.add_argument("--label", default="")
    p.add_argument("--header", action="store_true")
    a = p.parse_args()
    ref = read(a.reference)
    imgs = [read(x, a.layer) for x in a.images]
    for x in imgs:
        if x.shape != ref.shape:
            raise SystemExit(f"error_split.py: {x.shape[1]}x{x.shape[0]} image against a "
                             f"{ref.shape[1]}x{ref.shape[0]} reference")
    ref_noise, ref_var = 0.0, np.zeros_like(ref)
    if a.pt:
        pts = []
        for x in a.pt:  # an undenoised PT pair: a --denoise render's raw layer where it has one
            try:
                pts.append(read(x, "raw"))
            except KeyError:
                pts.append(read(x))
        pt_var = rel_mse(pts[0], pts[1], ref) / 2
        ref_noise = max(0.0, np.mean([rel_mse(x, ref, ref) for x in pts]) - pt_var)
        # the reference's per-pixel variance: PT's pair's spread scaled by the reference's share of it
        ref_var = (pts[0] - pts[1]) ** 2 / 2 * (ref_noise / pt_var if pt_var > 0 else 0.0)
    errors = [rel_mse(x, ref, ref) for x in imgs]
    variance = rel_mse(imgs[0], imgs[1], ref) / 2
    bias2 = float(np.mean(errors)) - variance - ref_noise
    try:
        stderr = read(a.images[0], "stderr")
    except KeyError:
        stderr = np.zeros_like(ref)
    med, p99, worst, over, lit, z = block_stats(imgs[0], ref, stderr, ref_var)
    if a.header:
        print("| method | relMSE (two seeds) | variance | bias² | reference's own | blocks: median / 99th / max "
              "| blocks off > 5 % | worst \\|z\\| |")
        print("|---|---|---|---|---|---|---|---|")
    print(f"| {a.label} | {errors[0]:.3g} / {errors[1]:.3g} | {variance:.3g} | {bias2:.2g} | {ref_noise:.2g} | "
          f"{100 * med:.2f} / {100 * p99:.1f} / {100 * worst:.1f} % | {over} of {lit} | {z:.1f} |")


if __name__ == "__main__":
    main()
