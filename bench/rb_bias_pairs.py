#!/usr/bin/env python3
"""RB's bias in a combined render, seen by two seeds, against what the render's own check counted
(docs/results.md, "Regional error": the check of RB's bias under the regional level).

  rb_bias_pairs.py SEED1.exr SEED2.exr SEED1.json SEED2.json [--reference R1.exr R2.exr] [--downsample K]

SEEDn.exr: `bundlepath render ... --seed n --out SEEDn` (with `--layers all` for the pt_raw layer);
SEEDn.json: its --stats. Two independent renders' errors are independent, so the mean over values of
their product, each over (R^2 + 0.01) as the relMSE (docs/design.md section 7), is the square of what
they share: the bias. Two estimates of it:
  * through PT: (image - pt_raw) is RB's layer as it counts less PT's estimate of RB's share, whose
    expectation is RB's bias alone (needs --layers all);
  * through the references: (image - R) of each seed, less the references' own noise (two
    independent references R1, R2; R their mean, its noise a quarter of their difference's relMSE).
For each seed: the check's estimate and standard error (rb_bias_check), the estimated relMSE, and
the measured relMSE less the reference's own noise. --downsample K: the references are K times the
renders' size (box filter: a pixel's K x K mean is the smaller render's pixel).
Needs numpy and OpenEXR (the peers' venv). Prints Markdown lines.
"""
import argparse
import json

import numpy as np
import OpenEXR


def load(path, layer=""):
    with OpenEXR.File(path, separate_channels=True) as f:
        ch = f.channels()
        names = [layer + c for c in ("R", "G", "B")]
        if not all(n in ch for n in names):
            return None
        return np.stack([np.asarray(ch[n].pixels, dtype=np.float64) for n in names], axis=-1)


def downsample(x, k):
    h, w = x.shape[0] // k, x.shape[1] // k
    return x[:h * k, :w * k].reshape(h, k, w, k, 3).mean(axis=(1, 3))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("images", nargs=2)
    p.add_argument("stats", nargs=2)
    p.add_argument("--reference", nargs=2)
    p.add_argument("--downsample", type=int, default=1)
    a = p.parse_args()
    img = [load(x) for x in a.images]
    raw = [load(x, "pt_raw.") for x in a.images]
    ref_mean, ref_own = None, None
    if a.reference:
        r1, r2 = (downsample(load(x), a.downsample) for x in a.reference)
        ref_mean = 0.5 * (r1 + r2)
    den = (ref_mean if ref_mean is not None else 0.5 * (img[0] + img[1])) ** 2 + 0.01
    if ref_mean is not None:
        ref_own = float(np.mean((r1 - r2) ** 2 / den)) / 4.0
    line = []
    if raw[0] is not None and raw[1] is not None:
        line.append("bias^2 through PT %.6f" % np.mean((img[0] - raw[0]) * (img[1] - raw[1]) / den))
    if ref_mean is not None:
        shared = float(np.mean((img[0] - ref_mean) * (img[1] - ref_mean) / den))
        line.append("through the references %.6f (their own %.6f taken off)" % (shared - ref_own, ref_own))
    print("; ".join(line))
    for k in range(2):
        e = json.load(open(a.stats[k]))["error_estimate"]
        c = e["rb_bias_check"]
        out = "seed %d: check %.6f +- %.6f (%d batches), estimated relMSE %.6f" % (
            k + 1, c["estimate"], c["standard_error"], c["batches"], e["levels"][0]["estimated_rel_mse"])
        if ref_mean is not None:
            measured = float(np.mean((img[k] - ref_mean) ** 2 / den)) - ref_own
            out += ", measured less the references' own %.6f, estimated / measured %.2f" % (
                measured, e["levels"][0]["estimated_rel_mse"] / measured)
        print(out)


if __name__ == "__main__":
    main()
