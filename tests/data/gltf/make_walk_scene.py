#!/usr/bin/env python3
"""Writes good/cornell-walk.gltf: scenes/cornell-box.gltf with three camera nodes, for the
walkthrough tests (python3 stdlib only; run from anywhere).

Camera nodes, in scene order: 0 "camera" (the box's own view), 1 "left" (from the left, turned 20
degrees), 2 "walker", a child of "rig" (translated by +0.1 in x) and animated by "walk": its
translation LINEAR from (0.178, 0.273, -0.8) at t = 0 to (0.178, 0.273, -0.4) at t = 1, its rotation
STEP from 180 degrees about y (looking down +z) to 160 degrees at t = 0.5; at rest (no animation)
it stands at (0.178, 0.273, -0.6) in the rig, looking down +z.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))


def about_y(degrees):
    half = math.radians(degrees) / 2
    return [0.0, math.sin(half), 0.0, math.cos(half)]


def main():
    with open(os.path.join(ROOT, "scenes", "cornell-box.gltf")) as f:
        d = json.load(f)
    camera = d["nodes"][4]
    d["nodes"] += [
        {"name": "left", "camera": 0, "translation": [0.1, 0.3, -0.7], "rotation": about_y(200.0)},
        {"name": "rig", "translation": [0.1, 0.0, 0.0], "children": [7]},
        {"name": "walker", "camera": 0, "translation": [0.178, 0.273, -0.6], "rotation": camera["rotation"]},
    ]
    d["scenes"][0]["nodes"] += [5, 6]
    # Animation data in a buffer of its own: translation times, values; rotation times, values.
    t_times = [0.0, 1.0]
    t_values = [0.178, 0.273, -0.8, 0.178, 0.273, -0.4]
    r_times = [0.0, 0.5]
    r_values = about_y(180.0) + about_y(160.0)
    blob = struct.pack("<2f", *t_times) + struct.pack("<6f", *t_values) + struct.pack("<2f", *r_times) + \
        struct.pack("<8f", *r_values)
    buffer = len(d["buffers"])
    d["buffers"].append({"byteLength": len(blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()})
    first_view = len(d["bufferViews"])
    offset = 0
    for length in (8, 24, 8, 32):
        d["bufferViews"].append({"buffer": buffer, "byteOffset": offset, "byteLength": length})
        offset += length
    first_accessor = len(d["accessors"])
    d["accessors"] += [
        {"bufferView": first_view, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]},
        {"bufferView": first_view + 1, "componentType": 5126, "count": 2, "type": "VEC3"},
        {"bufferView": first_view + 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [0.5]},
        {"bufferView": first_view + 3, "componentType": 5126, "count": 2, "type": "VEC4"},
    ]
    d["animations"] = [{
        "name": "walk",
        "samplers": [
            {"input": first_accessor, "output": first_accessor + 1, "interpolation": "LINEAR"},
            {"input": first_accessor + 2, "output": first_accessor + 3, "interpolation": "STEP"},
        ],
        "channels": [
            {"sampler": 0, "target": {"node": 7, "path": "translation"}},
            {"sampler": 1, "target": {"node": 7, "path": "rotation"}},
        ],
    }]
    with open(os.path.join(HERE, "good", "cornell-walk.gltf"), "w") as f:
        json.dump(d, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
