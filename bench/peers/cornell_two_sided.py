#!/usr/bin/env python3
"""Writes a variant of scenes/cornell-box.gltf for the conventions check of double-sided emitters
(issue 29): the light's material `doubleSided` and the light lowered by DROP metres (0.15), so its
back face lights the ceiling. Standard library only.

  python3 bench/peers/cornell_two_sided.py OUT.gltf [DROP]
"""
import json
import os
import sys


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write("usage: cornell_two_sided.py OUT.gltf [DROP]\n")
        return 2
    drop = float(argv[2]) if len(argv) == 3 else 0.15
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "cornell-box.gltf")
    with open(src) as f:
        gltf = json.load(f)
    light = next(i for i, m in enumerate(gltf["materials"]) if m.get("name") == "light")
    gltf["materials"][light]["doubleSided"] = True
    mesh = next(i for i, m in enumerate(gltf["meshes"]) if any(p.get("material") == light for p in m["primitives"]))
    for node in gltf["nodes"]:
        if node.get("mesh") == mesh:
            node["translation"] = [0.0, -drop, 0.0]
    gltf["asset"]["generator"] = "bundlepath bench/peers/cornell_two_sided.py (from scenes/cornell-box.gltf)"
    with open(argv[1], "w") as f:
        json.dump(gltf, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
