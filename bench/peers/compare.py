"""Image against reference, the figures of the peer table (issue 29). Runs in the peers' venv
(numpy, OpenEXR):

  python bench/peers/compare.py IMAGE.exr REFERENCE.exr [--grid 8] [--stats STATS.json]
                                 [--reference-stats REFERENCE.json] [--second IMAGE2.exr]
                                                                         -> one JSON line

* rel_mse: mean over pixels and RGB channels of (I - R)^2 / (R^2 + 0.01), bundlepath's definition
  (`bundlepath compare`, host/image/image.h);
* worst_block: the largest relative error |mean_b(I) - mean_b(R)| / mean_b(R) of the luminance
  (Rec. 709) averaged over each block of a GRID x GRID grid (pixel (x, y) in block
  (x·GRID / width, y·GRID / height), as `render --regions` and bench/regional_error.sh cut images:
  80 x 45 pixels at 640x360), over the blocks whose reference mean is at least 1 % of the image's
  (black regions have no relative error);
* mean, reference_mean, mean_rel: the image's mean luminance, the reference's, and their relative
  difference;
* with --stats (a bundlepath render's `--stats` file, its `regional_error` on the same grid):
  worst_block_z, the worst block's error over the standard error the render reported for it
  (combined with the reference's own where --reference-stats has it on the same grid), and max_abs_z,
  the largest |z| over the blocks: whether an error is one the render says it has (|z| of 3 and more
  over 64 blocks is rare for noise alone).
* with --second (the same renderer's render at another seed): seeds_rel_mse, the mean over pixels
  and channels of (I - I2)^2 / (R^2 + 0.01), the reference in the denominator so that the
  denominator holds no noise: its expectation is twice the image's own variance in relMSE's units,
  so noise_rel_mse = seeds_rel_mse / 2 is the image's noise alone, and rel_mse less it (and less the
  reference's own) is what the image holds beyond noise: a model difference or a bias.
"""
import argparse
import json
import sys

import numpy as np
import OpenEXR


def read_rgb(path):
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            img = np.asarray(channels["RGB"].pixels, dtype=np.float64)
        elif "RGBA" in channels:
            img = np.asarray(channels["RGBA"].pixels, dtype=np.float64)[..., :3]
        else:
            names = sorted(channels)
            pick = {c: next((n for n in names if n == c or n.endswith("." + c)), None) for c in "RGB"}
            if None in pick.values():
                raise SystemExit("%s: no R, G, B channels (has %s)" % (path, ", ".join(names)))
            img = np.stack([np.asarray(channels[pick[c]].pixels, dtype=np.float64) for c in "RGB"], axis=-1)
    return img


def luminance(img):
    return img @ np.array([0.2126, 0.7152, 0.0722])


def block_means(lum, grid):
    h, w = lum.shape
    rows = np.arange(h) * grid // h  # the block row of each pixel row (host/image/regions.h)
    cols = np.arange(w) * grid // w
    return np.array([lum[rows == by][:, cols == bx].mean() for by in range(grid) for bx in range(grid)])


def stderr_on_grid(stats_path, grid):
    """The relative standard error per block that a bundlepath render reported, or None."""
    regional = json.load(open(stats_path)).get("regional_error")
    if regional and list(regional.get("regions", [])) == [grid, grid]:
        return np.array([np.nan if e is None else e for e in regional["relative_stderr"]], dtype=np.float64)
    print("compare.py: %s has no regional error on a %d x %d grid" % (stats_path, grid, grid), file=sys.stderr)
    return None


def check_comparable(image, reference):
    if image.shape != reference.shape:
        raise SystemExit("sizes differ: %s vs %s" % (image.shape, reference.shape))
    if not np.all(np.isfinite(image)):
        raise SystemExit("the image has non-finite pixels")


def compare(image, reference, grid=8, reported_stderr=None, reference_stderr=None):
    check_comparable(image, reference)
    rel_mse = float(np.mean((image - reference) ** 2 / (reference ** 2 + 0.01)))
    li, lr = luminance(image), luminance(reference)
    bi, br = block_means(li, grid), block_means(lr, grid)
    keep = br >= 0.01 * lr.mean()
    rel = np.abs(bi[keep] - br[keep]) / br[keep]
    result = {"rel_mse": rel_mse, "worst_block": float(rel.max()) if rel.size else 0.0, "grid": grid,
              "mean": float(li.mean()), "reference_mean": float(lr.mean()),
              "mean_rel": float(li.mean() / lr.mean() - 1.0)}
    if reported_stderr is not None and rel.size:
        # z = (Y - R) / R over sqrt(σ² + σ_R²): the render's own relative standard error and the
        # reference's, as bench/regional_error.sh
        var = reported_stderr ** 2 + (reference_stderr ** 2 if reference_stderr is not None else 0.0)
        z = (bi[keep] - br[keep]) / br[keep] / np.sqrt(var[keep])
        result["worst_block_z"] = float(z[np.argmax(rel)])
        result["max_abs_z"] = float(np.nanmax(np.abs(z)))
    return result


def seed_pair(image, second, reference):
    check_comparable(second, reference)
    seeds_rel_mse = float(np.mean((image - second) ** 2 / (reference ** 2 + 0.01)))
    return {"seeds_rel_mse": seeds_rel_mse, "noise_rel_mse": 0.5 * seeds_rel_mse}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("image")
    p.add_argument("reference")
    p.add_argument("--grid", type=int, default=8)
    p.add_argument("--stats", help="the render's --stats JSON: z of each block against its own error")
    p.add_argument("--reference-stats", help="the reference's --stats JSON: its own error joins the z")
    p.add_argument("--second", help="the same renderer at another seed: the image's own noise")
    a = p.parse_args()
    stderr = stderr_on_grid(a.stats, a.grid) if a.stats else None
    ref_stderr = stderr_on_grid(a.reference_stats, a.grid) if a.reference_stats else None
    image, reference = read_rgb(a.image), read_rgb(a.reference)
    result = compare(image, reference, a.grid, stderr, ref_stderr)
    if a.second:
        result.update(seed_pair(image, read_rgb(a.second), reference))
    print(json.dumps(result))


if __name__ == "__main__":
    sys.exit(main())
