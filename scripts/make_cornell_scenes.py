#!/usr/bin/env python3
"""Writes scenes/cornell-box.gltf, scenes/cornell-glossy.gltf, scenes/cornell-ggx.gltf,
scenes/cornell-normal-map.gltf and scenes/cornell-glass.gltf (python3 stdlib only).

Geometry: the published Cornell Box data (/work/shared/data/cornell-box.md), mm -> m, y up.
Every quad is checked to face the way it must: walls into the box, block faces out of the
blocks, the light down. Materials use extras.phong (docs/design.md section 6); the light has kd = 0
(a pure emitter, so RB and PT do not disagree about light reflected by the lamp) and
Le = emissiveFactor (1, 12/17, 4/17) x KHR_materials_emissive_strength 17 = (17, 12, 4).
pbrMetallicRoughness mirrors the Phong values so other viewers show similar colours.

Usage: python3 scripts/make_cornell_scenes.py [output folder, default: <repo>/scenes]
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

MM = 0.001
LIGHT_Y = 548.7  # 0.1 mm below the ceiling, so the two never coincide

class Away:
    """A block face's front must face away from the block's centre."""
    def __init__(self, centre):
        self.centre = centre


# (name, material, quad in the published order, the direction its front must face)
SHORT_CENTRE = Away((186.0, 82.5, 168.5))
TALL_CENTRE = Away((368.5, 165.0, 351.5))
FACES = [
    ("light", "light", [(343.0, LIGHT_Y, 227.0), (343.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 227.0)], (0, -1, 0)),
    ("floor", "floor", [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)], (0, 1, 0)),
    ("ceiling", "white", [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)], (0, -1, 0)),
    ("back wall", "back", [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)], (0, 0, -1)),
    ("right wall", "green", [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)], (1, 0, 0)),
    ("left wall", "red", [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)], (-1, 0, 0)),
    ("short block top", "short block", [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)], (0, 1, 0)),
    ("short block side", "short block", [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)], SHORT_CENTRE),
    ("short block side", "short block", [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)], SHORT_CENTRE),
    ("short block side", "short block", [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)], SHORT_CENTRE),
    ("short block side", "short block", [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)], SHORT_CENTRE),
    ("tall block top", "block", [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)], (0, 1, 0)),
    ("tall block side", "block", [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)], TALL_CENTRE),
    ("tall block side", "block", [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)], TALL_CENTRE),
    ("tall block side", "block", [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)], TALL_CENTRE),
    ("tall block side", "block", [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)], TALL_CENTRE),
]

WHITE = (0.725, 0.71, 0.68)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)


def lambert(kd):
    return {"kd": list(kd), "ks": [0.0, 0.0, 0.0], "shininess": 1.0}


def phong(kd, ks, n):
    return {"kd": list(kd), "ks": list(ks), "shininess": float(n)}


LIGHT = {"phong": lambert((0.0, 0.0, 0.0)), "emission": (1.0, 12.0 / 17.0, 4.0 / 17.0), "strength": 17.0}

# Material sets: name -> {"phong": ..., optional "emission"/"strength"}; a face's material key maps here.
BOX_MATERIALS = {
    "white": {"phong": lambert(WHITE)}, "red": {"phong": lambert(RED)},
    "green": {"phong": lambert(GREEN)}, "light": LIGHT,
}
BOX_KEYS = {"floor": "white", "back": "white", "white": "white", "block": "white", "short block": "white",
            "red": "red", "green": "green", "light": "light"}

# The paper's glossy figures on the public box: floor and back wall ks 0.85 n 50 with a faint
# white-ish diffuse part (kd + ks <= 1 per channel); blocks kd 0.5 ks 0.5 n 10; egg kd 0.1 ks 0.8 n 10.
GLOSSY_KD = tuple(round(0.15 * c / WHITE[0], 4) for c in WHITE)
GLOSSY_MATERIALS = {
    "glossy white": {"phong": phong(GLOSSY_KD, (0.85,) * 3, 50)},
    "white": {"phong": lambert(WHITE)}, "red": {"phong": lambert(RED)},
    "green": {"phong": lambert(GREEN)},
    "block": {"phong": phong((0.5,) * 3, (0.5,) * 3, 10)},
    "egg": {"phong": phong((0.1,) * 3, (0.8,) * 3, 10)},
    "light": LIGHT,
}
GLOSSY_KEYS = {"floor": "glossy white", "back": "glossy white", "white": "white", "block": "block", "short block": "block",
               "red": "red", "green": "green", "light": "light"}

# The glossy box with glTF's metallic-roughness materials instead (GGX, docs/design.md section 11): a glossy
# white dielectric floor and back wall (roughness 0.3), a rough gold block (0.2), a red plastic one
# (0.5), a copper egg (0.35); the side walls Lambert (metallic 0, specularFactor 0).
def pbr(base, metallic, roughness, specular=1.0):
    return {"base": list(base), "metallic": metallic, "roughness": roughness, "specular": specular}


GGX_MATERIALS = {
    "glossy white": {"pbr": pbr(WHITE, 0.0, 0.3)},
    "white": {"pbr": pbr(WHITE, 0.0, 1.0, 0.0)}, "red": {"pbr": pbr(RED, 0.0, 1.0, 0.0)},
    "green": {"pbr": pbr(GREEN, 0.0, 1.0, 0.0)},
    "gold": {"pbr": pbr((1.0, 0.78, 0.34), 1.0, 0.2)},
    "red plastic": {"pbr": pbr((0.6, 0.05, 0.04), 0.0, 0.5)},
    "egg": {"pbr": pbr((0.95, 0.64, 0.54), 1.0, 0.35)},
    "light": LIGHT,
}
GGX_KEYS = {"floor": "glossy white", "back": "glossy white", "white": "white", "block": "gold",
            "short block": "red plastic",
            "red": "red", "green": "green", "light": "light"}

# The Lambert box with a solid glass egg (KHR_materials_transmission with KHR_materials_volume: it
# refracts, docs/design.md section 11): clear, ior 1.5, faintly green, 80 % of red left after 0.2 m.
GLASS_MATERIALS = dict(BOX_MATERIALS)
GLASS_MATERIALS["glass"] = {"pbr": pbr((1.0, 1.0, 1.0), 0.0, 0.0),
                            "volume": {"ior": 1.5, "thickness": 0.1, "colour": (0.8, 0.95, 0.9), "distance": 0.2}}

# The plain box with glTF materials (Lambert: metallic 0, specularFactor 0) and a back wall of bumps: a
# normalTexture (an egg-crate height field, written below as a PNG) repeated 4 x 4 times over the wall.
# No NORMAL and no TANGENT: the loader takes flat normals and generates the tangents, as glTF asks.
BUMP_REPEATS = 4.0
BUMP_TEXELS = 64
BUMP_HEIGHT = 0.12  # of the height field, in texture widths: slopes up to 2 pi 0.12 / (1/2) ~ 1.5 (56 degrees)


def back_wall_uv(p):
    """u to the viewer's right (-x), v down the wall (-y): the image upright as the camera sees it."""
    return ((0.556 - p[0]) / 0.556 * BUMP_REPEATS, (0.5488 - p[1]) / 0.5488 * BUMP_REPEATS)


NORMAL_MAP_MATERIALS = {
    "bumpy white": {"pbr": pbr(WHITE, 0.0, 1.0, 0.0), "normal map": back_wall_uv},
    "white": {"pbr": pbr(WHITE, 0.0, 1.0, 0.0)}, "red": {"pbr": pbr(RED, 0.0, 1.0, 0.0)},
    "green": {"pbr": pbr(GREEN, 0.0, 1.0, 0.0)},
    "light": LIGHT,
}
NORMAL_MAP_KEYS = {"floor": "white", "back": "bumpy white", "white": "white", "block": "white", "short block": "white",
                   "red": "red", "green": "green", "light": "light"}


def egg_crate_normals(n, height):
    """RGB rows of a tangent-space normal map of h(x, y) = height sin(2 pi 2x) sin(2 pi 2y) over the unit
    texture (x right, y up the image): n = normalize(-dh/dx, -dh/dy, 1), stored as (n + 1)/2 (glTF)."""
    rows = []
    for row in range(n):
        y = 1.0 - (row + 0.5) / n  # rows run down the image
        line = bytearray()
        for col in range(n):
            x = (col + 0.5) / n
            k = 4.0 * math.pi
            dx = height * k * math.cos(k * x) * math.sin(k * y)
            dy = height * k * math.sin(k * x) * math.cos(k * y)
            length = math.sqrt(dx * dx + dy * dy + 1.0)
            line += bytes(round((c / length * 0.5 + 0.5) * 255) for c in (-dx, -dy, 1.0))
        rows.append(bytes(line))
    return rows


def png(rows, width):
    """An 8-bit RGB PNG of `rows` (zlib, no filtering)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    header = struct.pack(">IIBBBBB", width, len(rows), 8, 2, 0, 0, 0)
    raw = b"".join(b"\0" + r for r in rows)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


# Egg: an ellipsoid standing on the floor in the open space in front of the short block, on the
# red (image-left, +x) side.
EGG_CENTRE = (0.42, 0.0, 0.12)
EGG_RADIUS = 0.09
EGG_STRETCH_Y = 1.3
EGG_SEGMENTS, EGG_RINGS = 36, 22


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def normal(t): return cross(sub(t[1], t[0]), sub(t[2], t[0]))
def centroid(pts): return tuple(sum(c) / len(pts) for c in zip(*pts))


def quad_triangles(name, quad, facing):
    """Two triangles (0,1,2), (0,2,3) of a quad, after asserting its front faces `facing`."""
    tris = [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    for t in tris:
        want = sub(centroid(t), facing.centre) if isinstance(facing, Away) else facing
        assert dot(normal(t), want) > 0, f"{name}: winding faces the wrong way"
    return [tuple(tuple(c * MM for c in p) for p in t) for t in tris]


def egg_triangles():
    cx, cy, cz = EGG_CENTRE
    ry = EGG_RADIUS * EGG_STRETCH_Y
    cy += ry + 0.0005  # rests on the floor with a hair of clearance

    def vertex(ring, seg):
        theta = math.pi * ring / EGG_RINGS  # from the top pole
        phi = 2.0 * math.pi * seg / EGG_SEGMENTS
        return (cx + EGG_RADIUS * math.sin(theta) * math.cos(phi), cy + ry * math.cos(theta),
                cz + EGG_RADIUS * math.sin(theta) * math.sin(phi))

    tris = []
    for ring in range(EGG_RINGS):
        for seg in range(EGG_SEGMENTS):
            a, b = vertex(ring, seg), vertex(ring, seg + 1)
            c, d = vertex(ring + 1, seg), vertex(ring + 1, seg + 1)
            if ring > 0:
                tris.append((a, b, c))
            if ring < EGG_RINGS - 1:
                tris.append((b, d, c))
    centre = (cx, cy, cz)
    for t in tris:
        assert dot(normal(t), sub(centroid(t), centre)) > 0, "egg triangle faces inwards"
    # Clear of the blocks (their footprints are convex quads in x-z) and the walls.
    for block in (FACES[7:11], FACES[12:16]):
        for _, _, quad, facing in block:
            n = normal((quad[0], quad[1], quad[2]))
            n = (n[0], 0.0, n[2])
            length = math.sqrt(dot(n, n))
            # signed distance of the egg centre from the side's plane, outward positive
            dist = dot(sub((cx / MM, 0.0, cz / MM), quad[0]), n) / length * MM
            if dist > EGG_RADIUS + 0.01:
                break
        else:
            raise AssertionError("egg intersects a block")
    assert EGG_RADIUS + 0.01 < cx < 0.549 - EGG_RADIUS - 0.01 and cz > EGG_RADIUS + 0.01
    return tris


def gltf(materials, keys, extra_meshes):
    """One mesh (and node) per material; indexed, unsigned-short indices, one embedded buffer."""
    groups = {name: [] for name in materials}
    for name, key, quad, facing in FACES:
        groups[keys[key]] += quad_triangles(name, quad, facing)
    for key, tris in extra_meshes.items():
        groups[key] += tris
    blob = bytearray()
    doc = {
        "asset": {"version": "2.0", "generator": "bundlepath scripts/make_cornell_scenes.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
        "accessors": [], "bufferViews": [], "buffers": [],
        "cameras": [{"type": "perspective", "name": "Cornell camera (35 mm lens, 25 mm film)",
                     "perspective": {"yfov": 2.0 * math.atan(12.5 / 35.0), "aspectRatio": 1.0, "znear": 0.01}}],
    }
    for name, m in materials.items():
        if "pbr" in m:
            p = m["pbr"]
            mat = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": p["base"] + [1.0],
                                                          "metallicFactor": p["metallic"],
                                                          "roughnessFactor": p["roughness"]}}
            if p["specular"] != 1.0:
                mat["extensions"] = {"KHR_materials_specular": {"specularFactor": p["specular"]}}
                if "KHR_materials_specular" not in doc["extensionsUsed"]:
                    doc["extensionsUsed"].append("KHR_materials_specular")
            if "normal map" in m:
                add_normal_texture(doc, mat)
            if "volume" in m:
                v = m["volume"]
                mat.setdefault("extensions", {}).update({
                    "KHR_materials_transmission": {"transmissionFactor": 1.0},
                    "KHR_materials_ior": {"ior": v["ior"]},
                    "KHR_materials_volume": {"thicknessFactor": v["thickness"], "attenuationColor": list(v["colour"]),
                                             "attenuationDistance": v["distance"]}})
                for e in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"):
                    if e not in doc["extensionsUsed"]:
                        doc["extensionsUsed"].append(e)
            doc["materials"].append(mat)
            continue
        ph = m["phong"]
        roughness = math.sqrt(math.sqrt(2.0 / (ph["shininess"] + 2.0)))  # inverse of n = 2/a^2 - 2, a = r^2
        mat = {"name": name, "extras": {"phong": ph},
               "pbrMetallicRoughness": {"baseColorFactor": ph["kd"] + [1.0], "metallicFactor": 0.0,
                                        "roughnessFactor": round(roughness, 4)}}
        if "emission" in m:
            mat["emissiveFactor"] = list(m["emission"])
            mat["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": m["strength"]}}
        doc["materials"].append(mat)
    for mi, (name, tris) in enumerate(groups.items()):
        if not tris:
            continue
        verts, index_of, indices = [], {}, []
        for t in tris:
            for p in t:
                p = tuple(round(c, 7) for c in p)
                if p not in index_of:
                    index_of[p] = len(verts)
                    verts.append(p)
                indices.append(index_of[p])
        assert len(verts) < 65536
        pos_offset = len(blob)
        for p in verts:
            blob += struct.pack("<3f", *p)
        uv = materials[name].get("normal map")
        uv_offset = len(blob)
        for p in verts if uv else []:
            blob += struct.pack("<2f", *uv(p))
        idx_offset = len(blob)
        blob += struct.pack(f"<{len(indices)}H", *indices)
        blob += b"\0" * (-len(blob) % 4)
        views, accs = doc["bufferViews"], doc["accessors"]
        views.append({"buffer": 0, "byteOffset": pos_offset, "byteLength": uv_offset - pos_offset, "target": 34962})
        accs.append({"bufferView": len(views) - 1, "componentType": 5126, "count": len(verts), "type": "VEC3",
                     "min": [min(v[i] for v in verts) for i in range(3)],
                     "max": [max(v[i] for v in verts) for i in range(3)]})
        attributes = {"POSITION": len(accs) - 1}
        if uv:
            views.append({"buffer": 0, "byteOffset": uv_offset, "byteLength": idx_offset - uv_offset, "target": 34962})
            accs.append({"bufferView": len(views) - 1, "componentType": 5126, "count": len(verts), "type": "VEC2"})
            attributes["TEXCOORD_0"] = len(accs) - 1
        views.append({"buffer": 0, "byteOffset": idx_offset, "byteLength": 2 * len(indices), "target": 34963})
        accs.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        doc["meshes"].append({"name": name, "primitives": [
            {"attributes": attributes, "indices": len(accs) - 1, "material": mi}]})
        doc["nodes"].append({"name": name, "mesh": len(doc["meshes"]) - 1})
    # glTF cameras look down -z: half a turn about y makes this one look along +z, up +y, so
    # the red wall (+x) is on the image's left.
    doc["nodes"].append({"name": "camera", "camera": 0, "translation": [0.278, 0.273, -0.8],
                         "rotation": [0.0, 1.0, 0.0, 0.0]})
    doc["scenes"][0]["nodes"] = list(range(len(doc["nodes"])))
    doc["buffers"].append({"byteLength": len(blob),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    return doc


def add_normal_texture(doc, mat):
    """The egg-crate normal map as a PNG data: URI, bilinear and repeating, on material `mat`."""
    data = png(egg_crate_normals(BUMP_TEXELS, BUMP_HEIGHT), BUMP_TEXELS)
    doc.setdefault("samplers", []).append({"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497})
    doc.setdefault("images", []).append({"name": "egg-crate bumps",
                                         "uri": "data:image/png;base64," + base64.b64encode(data).decode()})
    doc.setdefault("textures", []).append({"sampler": len(doc["samplers"]) - 1, "source": len(doc["images"]) - 1})
    mat["normalTexture"] = {"index": len(doc["textures"]) - 1, "scale": 1.0}


def write(doc, path):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    size = os.path.getsize(path)
    assert size < 300_000, f"{path} is {size} bytes"
    print(f"wrote {path} ({size} bytes)")


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes")
    os.makedirs(out, exist_ok=True)
    for m in list(BOX_MATERIALS.values()) + list(GLOSSY_MATERIALS.values()):
        assert all(d + s <= 1.0 for d, s in zip(m["phong"]["kd"], m["phong"]["ks"])), m
    write(gltf(BOX_MATERIALS, BOX_KEYS, {}), os.path.join(out, "cornell-box.gltf"))
    write(gltf(GLOSSY_MATERIALS, GLOSSY_KEYS, {"egg": egg_triangles()}), os.path.join(out, "cornell-glossy.gltf"))
    write(gltf(GGX_MATERIALS, GGX_KEYS, {"egg": egg_triangles()}), os.path.join(out, "cornell-ggx.gltf"))
    write(gltf(NORMAL_MAP_MATERIALS, NORMAL_MAP_KEYS, {}), os.path.join(out, "cornell-normal-map.gltf"))
    write(gltf(GLASS_MATERIALS, BOX_KEYS, {"glass": egg_triangles()}), os.path.join(out, "cornell-glass.gltf"))


if __name__ == "__main__":
    main()
