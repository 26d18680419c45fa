#!/usr/bin/env python3
"""Writes scenes/glass-window.gltf (python3 stdlib only): a closed 4 m x 4 m x 2.6 m room lit only
by a sun through a glazed window, to show and test thin glass (KHR_materials_transmission,
thin-walled; docs/design.md section 11).

y up. The room spans x, z in [-2, 2], y in [0, 2.6]; every wall faces into the room. The -x wall
has a 1.4 m x 1.1 m opening (z in [-0.7, 0.7], y in [0.9, 2.0]) filled by a clear pane
(transmissionFactor 1, KHR_materials_ior 1.5, a faint green baseColor, doubleSided, no volume: a thin
pane as glTF defines it). Walls, floor and ceiling are Lambert (KHR_materials_specular with
specularColorFactor [0, 0, 0], as Blender's Specular 0). A directional light (KHR_lights_punctual,
13660 lux = 20 W/m^2 at 683 lm/W) shines in through the pane onto the floor; the camera looks at
the window and the sunlit patch.

Usage: python3 scripts/make_glass_window_scene.py [output folder, default: <repo>/scenes]
"""
import base64
import json
import math
import os
import struct
import sys

X0, X1, Z0, Z1, H = -2.0, 2.0, -2.0, 2.0, 2.6
WINDOW_Z = (-0.7, 0.7)
WINDOW_Y = (0.9, 2.0)
SUN_TRAVEL = (1.0, -0.75, 0.35)  # the direction sunlight travels: in through the window, down
SUN_LUX = 13660.0

MATERIALS = {
    "wall": {"base": (0.75, 0.73, 0.7)},
    "floor": {"base": (0.55, 0.45, 0.35)},
    "glass": {"base": (0.92, 0.96, 0.94), "glass": True},
}


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalize(v):
    n = math.sqrt(dot(v, v))
    return tuple(x / n for x in v)


def quad(corners, facing):
    """Two triangles of a planar quad whose front faces `facing`."""
    a, b, c, d = corners
    if dot(cross(sub(b, a), sub(c, a)), facing) < 0:
        a, b, c, d = d, c, b, a
    return [(a, b, c), (a, c, d)]


def room():
    """(material, triangles) of the room and the pane."""
    faces = {"wall": [], "floor": [], "glass": []}
    faces["floor"] += quad([(X0, 0, Z0), (X1, 0, Z0), (X1, 0, Z1), (X0, 0, Z1)], (0, 1, 0))
    faces["wall"] += quad([(X0, H, Z0), (X1, H, Z0), (X1, H, Z1), (X0, H, Z1)], (0, -1, 0))
    faces["wall"] += quad([(X1, 0, Z0), (X1, H, Z0), (X1, H, Z1), (X1, 0, Z1)], (-1, 0, 0))
    faces["wall"] += quad([(X0, 0, Z0), (X1, 0, Z0), (X1, H, Z0), (X0, H, Z0)], (0, 0, 1))
    faces["wall"] += quad([(X0, 0, Z1), (X1, 0, Z1), (X1, H, Z1), (X0, H, Z1)], (0, 0, -1))
    # the -x wall around its opening: below, above, and the two sides
    (wz0, wz1), (wy0, wy1) = WINDOW_Z, WINDOW_Y
    for (y0, y1, z0, z1) in [(0, wy0, Z0, Z1), (wy1, H, Z0, Z1), (wy0, wy1, Z0, wz0), (wy0, wy1, wz1, Z1)]:
        faces["wall"] += quad([(X0, y0, z0), (X0, y0, z1), (X0, y1, z1), (X0, y1, z0)], (1, 0, 0))
    faces["glass"] += quad([(X0, wy0, wz0), (X0, wy0, wz1), (X0, wy1, wz1), (X0, wy1, wz0)], (1, 0, 0))
    return faces


def rotation_from_minus_z(d):
    """Unit quaternion (x, y, z, w) turning -z onto the unit vector d (a glTF light shines along -z)."""
    a = (0.0, 0.0, -1.0)
    c = cross(a, d)
    w = 1.0 + dot(a, d)
    q = (c[0], c[1], c[2], w)
    n = math.sqrt(dot(q, q))
    return [round(x / n, 7) for x in q]


def look_rotation(forward, up=(0.0, 1.0, 0.0)):
    """Unit quaternion (x, y, z, w) of a camera looking along `forward` (glTF cameras look down -z)."""
    f = normalize(forward)
    r = normalize(cross(f, up))
    u = cross(r, f)
    # rotation matrix columns: x = r, y = u, z = -f
    m = [[r[0], u[0], -f[0]], [r[1], u[1], -f[1]], [r[2], u[2], -f[2]]]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    else:
        i = max(range(3), key=lambda k: m[k][k])
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k]) * 2
        q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / s]
        q[i] = 0.25 * s
        q[j] = (m[j][i] + m[i][j]) / s
        q[k] = (m[k][i] + m[i][k]) / s
    return [round(x, 7) for x in q]


def gltf():
    faces = room()
    blob = bytearray()
    doc = {
        "asset": {"version": "2.0", "generator": "bundlepath scripts/make_glass_window_scene.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_specular",
                           "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "color": [1.0, 0.95, 0.85], "intensity": SUN_LUX}]}},
        "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
        "accessors": [], "bufferViews": [], "buffers": [],
        "cameras": [{"type": "perspective", "name": "room camera",
                     "perspective": {"yfov": 1.0, "aspectRatio": 16.0 / 9.0, "znear": 0.01}}],
    }
    for name, m in MATERIALS.items():
        mat = {"name": name,
               "pbrMetallicRoughness": {"baseColorFactor": list(m["base"]) + [1.0], "metallicFactor": 0.0,
                                        "roughnessFactor": 0.0 if m.get("glass") else 1.0}}
        if m.get("glass"):
            mat["doubleSided"] = True
            mat["extensions"] = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                 "KHR_materials_ior": {"ior": 1.5}}
        else:
            mat["extensions"] = {"KHR_materials_specular": {"specularColorFactor": [0.0, 0.0, 0.0]}}
        doc["materials"].append(mat)
    for mi, name in enumerate(MATERIALS):
        verts, index_of, indices = [], {}, []
        for t in faces[name]:
            for p in t:
                p = tuple(round(float(c), 7) for c in p)
                if p not in index_of:
                    index_of[p] = len(verts)
                    verts.append(p)
                indices.append(index_of[p])
        pos_offset = len(blob)
        for p in verts:
            blob += struct.pack("<3f", *p)
        idx_offset = len(blob)
        blob += struct.pack(f"<{len(indices)}H", *indices)
        blob += b"\0" * (-len(blob) % 4)
        views, accs = doc["bufferViews"], doc["accessors"]
        views.append({"buffer": 0, "byteOffset": pos_offset, "byteLength": idx_offset - pos_offset, "target": 34962})
        views.append({"buffer": 0, "byteOffset": idx_offset, "byteLength": 2 * len(indices), "target": 34963})
        accs.append({"bufferView": len(views) - 2, "componentType": 5126, "count": len(verts), "type": "VEC3",
                     "min": [min(v[i] for v in verts) for i in range(3)],
                     "max": [max(v[i] for v in verts) for i in range(3)]})
        accs.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        doc["meshes"].append({"name": name, "primitives": [
            {"attributes": {"POSITION": len(accs) - 2}, "indices": len(accs) - 1, "material": mi}]})
        doc["nodes"].append({"name": name, "mesh": len(doc["meshes"]) - 1})
    doc["nodes"].append({"name": "sun", "rotation": rotation_from_minus_z(normalize(SUN_TRAVEL)),
                         "extensions": {"KHR_lights_punctual": {"light": 0}}})
    eye, target = (1.8, 1.5, -1.7), (-0.6, 0.6, 0.4)
    doc["nodes"].append({"name": "camera", "camera": 0, "translation": list(eye),
                         "rotation": look_rotation(sub(target, eye))})
    doc["scenes"][0]["nodes"] = list(range(len(doc["nodes"])))
    doc["buffers"].append({"byteLength": len(blob),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    return doc


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "glass-window.gltf")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(gltf(), f, indent=1)
        f.write("\n")
    print(f"wrote {path} ({os.path.getsize(path)} bytes)")


if __name__ == "__main__":
    main()
