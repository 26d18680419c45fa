#!/usr/bin/env python3
"""Where a combined image's error comes from, from K renders with equal work and different seeds
(docs/design.md §7's metric, per pixel and channel: (I - R)^2 / (R^2 + 0.01)). Python standard library only.

  bias_variance.py REFERENCE.exr IMAGE.exr...   (K >= 2 images with the pt and rb layers, or PT alone)

prints, averaged over pixels and channels (each term divided by R^2 + 0.01):
  var_pt, var_rb   the variance across seeds of the weighted pt and rb layers of one render
  cov              twice their covariance
  var_tot          the variance of one render's image (var_pt + var_rb + cov)
  mse_single       the mean relMSE of one render against the reference
  bias2_of_mean    (mean image - R)^2 less var_tot / K: the part that more samples do not remove,
                   i.e. the estimator's bias^2 plus the reference's own noise (a PT-alone run gives
                   the latter alone)
At k times the work of these renders, relMSE is about var_tot / k + bias2_of_mean.

Example (docs/results.md, "The default against each estimator"; a quarter of a 20 s render, four seeds):
  for s in 1 2 3 4; do build/bundlepath render scenes/cornell-glossy.gltf --width 128 --height 128 \\
    --mode combined --ratio 1/2 --eye-direct pt --spp 470 --seed $s --out /tmp/c$s; done
  bench/bias_variance.py REF.exr /tmp/c1.exr /tmp/c2.exr /tmp/c3.exr /tmp/c4.exr
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rb_regions import read_exr  # noqa: E402


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    ref = read_exr(argv[1])[2]
    imgs = [read_exr(p)[2] for p in argv[2:]]
    k = len(imgs)
    terms = dict.fromkeys(['var_pt', 'var_rb', 'cov', 'var_tot', 'mse_single', 'bias2_of_mean'], 0.0)
    n = 0
    for c in 'RGB':
        r_c = ref[c]
        pt_c = [im.get('pt.' + c, im[c]) for im in imgs]
        rb_c = [im.get('rb.' + c) for im in imgs]
        tot_c = [im[c] for im in imgs]
        for i in range(len(r_c)):
            d = r_c[i] * r_c[i] + 0.01
            pts = [x[i] for x in pt_c]
            rbs = [x[i] if x is not None else 0.0 for x in rb_c]
            ts = [x[i] for x in tot_c]
            mp, mr, mt = sum(pts) / k, sum(rbs) / k, sum(ts) / k
            vt = sum((x - mt) ** 2 for x in ts) / (k - 1)
            terms['var_pt'] += sum((x - mp) ** 2 for x in pts) / (k - 1) / d
            terms['var_rb'] += sum((x - mr) ** 2 for x in rbs) / (k - 1) / d
            terms['cov'] += 2 * sum((pts[j] - mp) * (rbs[j] - mr) for j in range(k)) / (k - 1) / d
            terms['var_tot'] += vt / d
            terms['mse_single'] += sum((x - r_c[i]) ** 2 for x in ts) / k / d
            terms['bias2_of_mean'] += ((mt - r_c[i]) ** 2 - vt / k) / d
            n += 1
    for name, value in terms.items():
        print(f'{name:>14}: {value / n:.3g}')


if __name__ == '__main__':
    main(sys.argv)
