#!/usr/bin/env python3
"""The PBR room's named regions, ours against Cycles (bench/results/pbr-room.md, "Reading the
figures"): for each region, mean luminance over both seeds of each side, ours / Cycles - 1.

  pbr_room_regions.py RUN_DIR [VARIANT_PREFIX]

RUN_DIR: bench/pbr_room.sh's --out (ours-pt-s1.exr, ours-pt-s2.exr, ours-combined-s*.exr,
cycles-s*.exr: the full scene, pt and combined). VARIANT_PREFIX (optional): a variant's renders,
PREFIX-pt-s1.exr, PREFIX-pt-s2.exr, PREFIX-cycles-s1.exr, PREFIX-cycles-s2.exr (the commands at
the end of pbr-room.md). Regions are pixels of the 320 x 180 image. Needs numpy and OpenEXR (the
peers' venv). Prints a Markdown table.
"""
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbr_room_compare import load_one, lum  # noqa: E402

REGIONS = [("sunlit floor patch", (131, 115, 169, 134)), ("near floor (magnified texture)", (0, 150, 120, 180)),
           ("far floor", (240, 95, 320, 125)), ("plaster wall (normal map)", (150, 0, 320, 60)),
           ("left wall beside the window", (0, 80, 20, 130)), ("window pane (reflection)", (45, 10, 100, 60)),
           ("gold sphere", (195, 85, 245, 122)), ("copper box", (205, 130, 270, 178)),
           ("red plastic", (135, 62, 180, 95)), ("whole image", (0, 0, 320, 180))]


def mean_luminance(paths):
    if not paths:
        raise SystemExit("pbr_room_regions.py: no renders found")
    return np.mean([lum(load_one(p)) for p in paths], axis=0)


def main():
    if len(sys.argv) not in (2, 3):
        raise SystemExit(__doc__)
    run = sys.argv[1]
    cycles = mean_luminance(sorted(glob.glob(os.path.join(run, "cycles-s*.exr"))))
    sets = {"full scene, pt": (mean_luminance(sorted(glob.glob(os.path.join(run, "ours-pt-s*.exr")))), cycles),
            "full scene, combined": (mean_luminance(sorted(glob.glob(os.path.join(run, "ours-combined-s*.exr")))),
                                     cycles)}
    if len(sys.argv) == 3:
        v = sys.argv[2]
        sets[os.path.basename(v) + ", pt"] = (mean_luminance(sorted(glob.glob(v + "-pt-s*.exr"))),
                                              mean_luminance(sorted(glob.glob(v + "-cycles-s*.exr"))))
    print("| region (pixels x0 y0 x1 y1) | " + " | ".join(sets) + " |")
    print("|---|" + "---|" * len(sets))
    for name, (x0, y0, x1, y1) in REGIONS:
        cells = ["%+.1f %%" % (100.0 * (a[y0:y1, x0:x1].mean() / b[y0:y1, x0:x1].mean() - 1.0))
                 for a, b in sets.values()]
        print("| %s (%d %d %d %d) | %s |" % (name, x0, y0, x1, y1, " | ".join(cells)))


if __name__ == "__main__":
    main()
