#!/usr/bin/env python3
"""Writes the small glTF files under tests/data/gltf/{good,bad}/ (python3 stdlib only).

Each bad file breaks exactly one thing of an otherwise valid one-triangle file, so the test that
loads it can assert which object the error message names. Run from anywhere; it writes beside itself.
"""
import base64
import copy
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OVERFLOW = 1.2345e300  # written as 1e400, which parses to infinity
TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def pack_triangles(positions, indices):
    """Float VEC3 positions then unsigned-short indices (padded to 4 bytes)."""
    blob = bytearray()
    for p in positions:
        blob += struct.pack("<3f", *p)
    pos_len = len(blob)
    blob += struct.pack(f"<{len(indices)}H", *indices)
    idx_len = len(blob) - pos_len
    blob += b"\0" * (-len(blob) % 4)
    return blob, pos_len, idx_len


def base(positions=TRIANGLE, indices=(0, 1, 2)):
    """A valid file: one indexed triangle, one material, one node, one scene."""
    blob, pos_len, idx_len = pack_triangles(positions, list(indices))
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3"},
            {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": pos_len},
            {"buffer": 0, "byteOffset": pos_len, "byteLength": idx_len},
        ],
        "buffers": [{"byteLength": len(blob)}],
    }
    return doc, blob


def embed(doc, blob):
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()
    return doc


def write_json(rel, doc):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    text = json.dumps(doc, indent=1).replace(str(OVERFLOW), "1e400")  # JSON has no inf literal
    with open(path, "w", encoding="utf-8") as f:
        f.write(text + "\n")


def write_bytes(rel, data):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


def glb(doc, blob, version=2):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    blob = bytes(blob) + b"\0" * (-len(blob) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    return struct.pack("<4sII", b"glTF", version, 12 + len(body)) + body


def bad(name, mutate, blob_mutate=None):
    doc, blob = base()
    mutate(doc)
    if blob_mutate:
        blob_mutate(blob)
    write_json(f"bad/{name}.gltf", embed(doc, blob))


def quad_mesh_file():
    """Two triangles of a unit quad in z = 0, counter-clockwise seen from +z."""
    return base([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], (0, 1, 2, 0, 2, 3))


def with_lights(lights, node_light):
    """A mutation: KHR_lights_punctual with `lights`, node 0 carrying light `node_light`."""
    def mutate(doc):
        doc.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
        doc.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": lights}
        doc["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": node_light}}})
        doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    return mutate


def with_normals(normals, count=None, accessor_type="VEC3", component=5126):
    """One triangle with a NORMAL accessor (2) holding `normals`; count, type and component overridable."""
    doc, blob = base()
    offset = len(blob)
    for n in normals:
        blob += struct.pack("<3f", *n)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob) - offset})
    doc["accessors"].append({"bufferView": 2, "componentType": component,
                             "count": len(normals) if count is None else count, "type": accessor_type})
    doc["buffers"][0]["byteLength"] = len(blob)
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 2
    return doc, blob


def png(width, height, rgba):
    """An RGBA8 PNG of `rgba` (rows top to bottom, 4 bytes a texel), stdlib only."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    rows = b"".join(b"\0" + bytes(rgba[y * width * 4:(y + 1) * width * 4]) for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


# The textured quad's 4 x 4 texels (RGBA8, rows top to bottom): distinct colours, alpha 255 but the
# top-right texel (alpha 64, for alphaMode MASK).
QUAD_TEXELS = [(40 + 60 * x, 30 + 70 * y, 200 - 40 * x - 10 * y, 64 if (x, y) == (3, 0) else 255)
               for y in range(4) for x in range(4)]


def textured_quad(image, texcoords=None, component=5126, normalized=False, accessor_type="VEC2", texture_index=0,
                  image_source=0, sampler=None):
    """The unit quad (z = 0, facing +z) with TEXCOORD_0 (accessor 2; uv = (x, 1 - y), glTF's uv origin at
    the image's top-left), a baseColorTexture of image 0 (`image`: the glTF image object), and a camera
    1 m in front of it whose 90-degree view the quad fills exactly."""
    doc, blob = quad_mesh_file()
    uv = texcoords or [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
    offset = len(blob)
    fmt = {5126: "f", 5121: "B", 5123: "H"}[component]
    for t in uv:
        blob += struct.pack("<" + fmt * len(t), *t)
    length = len(blob) - offset
    blob += b"\0" * (-len(blob) % 4)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": length})
    acc = {"bufferView": 2, "componentType": component, "count": len(uv), "type": accessor_type}
    if normalized:
        acc["normalized"] = True
    doc["accessors"].append(acc)
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
    doc["materials"][0] = {"name": "textured", "pbrMetallicRoughness": {"baseColorTexture": {"index": texture_index},
                                                                        "metallicFactor": 0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}
    doc["extensionsUsed"] = ["KHR_materials_specular"]
    doc["textures"] = [{"source": image_source, "sampler": 0}]
    doc["samplers"] = [sampler or {"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}]
    doc["images"] = [image]
    doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.pi / 2, "aspectRatio": 1.0, "znear": 0.01}}]
    doc["nodes"].append({"camera": 0, "translation": [0.5, 0.5, 0.5]})
    doc["scenes"][0]["nodes"].append(1)
    doc["buffers"][0]["byteLength"] = len(blob)
    return doc, blob


def quad_png():
    return png(4, 4, [c for t in QUAD_TEXELS for c in t])


def png_data_uri(data):
    return "data:image/png;base64," + base64.b64encode(data).decode()


def texture_files():
    write_bytes("good/textured-quad.png", quad_png())
    doc, blob = textured_quad({"uri": "textured-quad.png"})
    write_json("good/textured-quad.gltf", embed(doc, blob))
    # the same PNG from a buffer view, after the geometry
    doc, blob = textured_quad({"bufferView": 3, "mimeType": "image/png"})
    data = quad_png()
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
    blob += data
    blob += b"\0" * (-len(blob) % 4)
    doc["buffers"][0]["byteLength"] = len(blob)
    write_json("good/textured-quad-view.gltf", embed(doc, blob))
    # normalized unsigned-short texcoords
    doc, blob = textured_quad({"uri": "textured-quad.png"}, texcoords=[(0, 65535), (65535, 65535), (65535, 0), (0, 0)],
                              component=5123, normalized=True)
    write_json("good/textured-quad-ushort.gltf", embed(doc, blob))

    # alphaMode MASK (default cutoff 0.5): the top-right texel (alpha 64/255) is cut away
    doc, blob = textured_quad({"uri": "textured-quad.png"})
    doc["materials"][0]["alphaMode"] = "MASK"
    write_json("good/alpha-mask-quad.gltf", embed(doc, blob))

    doc, blob = textured_quad({"uri": "missing.png"})
    write_json("bad/texture-missing-image.gltf", embed(doc, blob))
    doc, blob = textured_quad({"uri": png_data_uri(b"this is not a PNG file at all")})
    write_json("bad/texture-undecodable.gltf", embed(doc, blob))
    # a header that says 20000 x 4 (and no image data worth decoding): refused before decoding
    header = quad_png()[:8] + struct.pack(">I", 13) + b"IHDR" + struct.pack(">IIBBBBB", 20000, 4, 8, 6, 0, 0, 0)
    header += struct.pack(">I", zlib.crc32(header[12:]) & 0xFFFFFFFF)
    doc, blob = textured_quad({"uri": png_data_uri(header + quad_png()[33:])})
    write_json("bad/texture-too-large.gltf", embed(doc, blob))
    doc, blob = textured_quad({"uri": "textured-quad.png"}, texcoords=[(0, 255), (255, 255), (255, 0), (0, 0)],
                              component=5121)
    write_json("bad/texcoord-unnormalized.gltf", embed(doc, blob))
    doc, blob = textured_quad({"uri": "textured-quad.png"}, texcoords=[(0, 1, 0), (1, 1, 0), (1, 0, 0), (0, 0, 0)],
                              accessor_type="VEC3")
    write_json("bad/texcoord-type.gltf", embed(doc, blob))
    doc, blob = textured_quad({"uri": "textured-quad.png"}, texture_index=5)
    write_json("bad/texture-index.gltf", embed(doc, blob))
    doc, blob = textured_quad({"uri": "textured-quad.png"}, image_source=3)
    write_json("bad/texture-image-index.gltf", embed(doc, blob))
    # the bad files that name textured-quad.png find it beside them
    write_bytes("bad/textured-quad.png", quad_png())


def good_files():
    # NORMAL: corner 1 tilted towards +x, corner 2 zero (the flat normal is used, with a warning),
    # under a node stretched 2x in x (normals transform by the inverse transpose).
    doc, blob = with_normals([(0.0, 0.0, 1.0), (0.7071068, 0.0, 0.7071068), (0.0, 0.0, 0.0)])
    doc["nodes"][0]["scale"] = [2.0, 1.0, 1.0]
    write_json("good/normals.gltf", embed(doc, blob))

    # KHR_lights_punctual: a spot light 2 m up, pointing down (the node's -z turned to -y), a point
    # light, and a directional light of 3 W/m^2 (2049 lux), shining along the node's -z.
    doc, blob = base()
    with_lights([{"type": "spot", "color": [1.0, 0.5, 0.25], "intensity": 683.0,
                  "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}},
                 {"type": "point", "intensity": 1366.0},
                 {"type": "directional", "intensity": 2049.0}], 0)(doc)
    doc["nodes"][-1].update(translation=[0.0, 2.0, 0.0], rotation=[-0.7071068, 0.0, 0.0, 0.7071068])
    for light in (1, 2):
        doc["nodes"].append({"translation": [1.0, 1.0, 1.0], "extensions": {"KHR_lights_punctual": {"light": light}}})
        doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    write_json("good/lights.gltf", embed(doc, blob))

    # External .bin beside the .gltf.
    doc, blob = base()
    doc["buffers"][0]["uri"] = "external-bin.bin"
    write_json("good/external-bin.gltf", doc)
    write_bytes("good/external-bin.bin", bytes(blob))

    # Binary glTF.
    doc, blob = base()
    write_bytes("good/triangle.glb", glb(doc, blob))

    # Materials: one primitive per material, all sharing the triangle's accessors.
    doc, blob = base()
    doc["materials"] = [
        {"name": "phong", "extras": {"phong": {"kd": [0.2, 0.3, 0.4], "ks": [0.5, 0.5, 0.5], "shininess": 20}},
         "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
        {"name": "pbr default"},
        {"name": "pbr", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 0.9, 1], "metallicFactor": 0.5,
                                                 "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.5}}},
        {"name": "too bright", "extras": {"phong": {"kd": [0.8, 0.2, 0.2], "ks": [0.8, 0.2, 0.2], "shininess": 5}}},
        {"name": "lamp", "emissiveFactor": [1.0, 0.5, 0.25], "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
        # Blender's exporter for Specular 0: white base colour, no specular lobe, no warning.
        {"name": "blender specular 0", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0},
         "extensions": {"KHR_materials_specular": {"specularColorFactor": [0, 0, 0]}}},
        {"name": "coloured specular", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                               "metallicFactor": 0.5},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.5, 0]}}},
        # KHR_materials_ior: water's 1.33 (f0 0.02), with a specular colour that f0 times it clamps to 1
        {"name": "water", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.4, 1], "metallicFactor": 0,
                                                   "roughnessFactor": 0.1},
         "extensions": {"KHR_materials_ior": {"ior": 1.33},
                        "KHR_materials_specular": {"specularColorFactor": [100, 1, 0.5]}}},
        # specular 0 and metallic 0: glTF's model is Lambert exactly
        {"name": "no specular", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0}}},
    ]
    doc["extensionsUsed"] = ["KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_materials_ior"]
    prim = doc["meshes"][0]["primitives"][0]
    doc["meshes"][0]["primitives"] = [dict(prim, material=i) for i in range(9)] + [
        {"attributes": {"POSITION": 0}, "indices": 1}]
    write_json("good/materials.gltf", embed(doc, blob))

    # Hierarchy: translated parent, scaled child, a mirrored instance of the same mesh, a camera.
    doc, blob = quad_mesh_file()
    doc["nodes"] = [
        {"translation": [10, 0, 0], "children": [1, 2]},
        {"scale": [2, 2, 2], "mesh": 0},
        {"matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -5, 0, 0, 1], "mesh": 0},
        {"translation": [0, 0, 5], "rotation": [0, math.sin(math.pi / 4), 0, math.cos(math.pi / 4)], "camera": 0},
    ]
    doc["scenes"] = [{"nodes": [0, 3]}]
    doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]
    write_json("good/hierarchy.gltf", embed(doc, blob))

    # No scenes: every root node is drawn (node 1 is a child of node 0, node 2 a root).
    doc, blob = base()
    del doc["scene"], doc["scenes"]
    doc["nodes"] = [{"children": [1]}, {"mesh": 0, "translation": [0, 0, 1]}, {"mesh": 0, "translation": [0, 0, 2]}]
    write_json("good/no-scenes.gltf", embed(doc, blob))

    # Only an orthographic camera: ignored, default view.
    doc, blob = base()
    doc["nodes"].append({"camera": 0, "translation": [0, 0, 3]})
    doc["scenes"][0]["nodes"] = [0, 1]
    doc["cameras"] = [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "zfar": 10, "znear": 0.1}}]
    write_json("good/ortho-camera.gltf", embed(doc, blob))

    # One good and one zero-area triangle.
    doc, blob = base([(0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 0, 0)], (0, 1, 2, 0, 1, 3))
    write_json("good/degenerate.gltf", embed(doc, blob))

    # Sparse accessor without a buffer view: positions start as zeros; the sparse part sets all three.
    doc, blob = base()
    sparse_idx = len(blob)
    blob += struct.pack("<3I", 0, 1, 2)
    sparse_val = len(blob)
    for p in [(0, 0, 1), (2, 0, 1), (0, 3, 1)]:
        blob += struct.pack("<3f", *p)
    doc["bufferViews"] += [{"buffer": 0, "byteOffset": sparse_idx, "byteLength": 12},
                           {"buffer": 0, "byteOffset": sparse_val, "byteLength": 36}]
    doc["buffers"][0]["byteLength"] = len(blob)
    doc["accessors"][0] = {"componentType": 5126, "count": 3, "type": "VEC3", "sparse": {
        "count": 3, "indices": {"bufferView": 2, "componentType": 5125}, "values": {"bufferView": 3}}}
    write_json("good/sparse-no-view.gltf", embed(doc, blob))

    # Interleaved positions in a strided view (stride 24: position + 12 bytes of something else).
    doc, _ = base()
    blob = bytearray()
    for p in TRIANGLE:
        blob += struct.pack("<3f", *p) + struct.pack("<3f", 9, 9, 9)
    idx = len(blob)
    blob += struct.pack("<3H", 0, 1, 2) + b"\0\0"
    doc["bufferViews"] = [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "byteStride": 24},
                          {"buffer": 0, "byteOffset": idx, "byteLength": 6}]
    doc["accessors"].append({"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 3, "type": "VEC3"})
    doc["buffers"][0]["byteLength"] = len(blob)
    write_json("good/strided.gltf", embed(doc, blob))


def bad_files():
    write_bytes("bad/not-gltf.gltf", b"this is not a glTF file\n")
    write_bytes("bad/syntax-error.gltf", b'{"asset": {"version": "2.0"}, "nodes": [}\n')
    doc, blob = base()
    write_bytes("bad/glb-version.glb", glb(doc, blob, version=1))
    write_bytes("bad/glb-truncated.glb", glb(doc, blob)[:40])

    def set_(path, value):
        def mutate(doc):
            obj = doc
            for key in path[:-1]:
                obj = obj[key]
            obj[path[-1]] = value
        return mutate

    bad("accessor-index", set_(["meshes", 0, "primitives", 0, "attributes", "POSITION"], 5))
    bad("indices-accessor-index", set_(["meshes", 0, "primitives", 0, "indices"], 7))
    bad("buffer-view-index", set_(["accessors", 0, "bufferView"], 4))
    bad("buffer-index", set_(["bufferViews", 0, "buffer"], 3))
    bad("accessor-past-view", set_(["accessors", 0, "byteOffset"], 4))
    bad("view-past-buffer", set_(["bufferViews", 1, "byteLength"], 64))
    bad("small-stride", set_(["bufferViews", 0, "byteStride"], 8))
    bad("index-value", lambda d: None, lambda b: b.__setitem__(slice(36, 38), struct.pack("<H", 3)))
    bad("material-index", set_(["meshes", 0, "primitives", 0, "material"], 2))
    bad("mesh-index", set_(["nodes", 0, "mesh"], 1))
    bad("camera-index", set_(["nodes", 0, "camera"], 0))
    bad("child-index", set_(["nodes", 0, "children"], [9]))
    bad("scene-node-index", set_(["scenes", 0, "nodes"], [0, 4]))
    bad("default-scene", set_(["scene"], 2))

    def cycle(doc):
        doc["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [2]}, {"children": [1]}]
    bad("node-cycle", cycle)
    bad("nan-position", lambda d: None, lambda b: b.__setitem__(slice(12, 16), struct.pack("<f", float("nan"))))
    bad("overflow-number", set_(["nodes", 0, "matrix"], [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, OVERFLOW, 0, 0, 1]))

    def overflow_transform(doc):  # each scale is finite; their product is not
        doc["nodes"] = [{"scale": [1e300, 1, 1], "children": [1]}, {"scale": [1e300, 1, 1], "mesh": 0}]
    bad("infinite-transform", overflow_transform)
    bad("normalized-positions", lambda d: d["accessors"][0].update(componentType=5123, normalized=True))
    bad("mode", set_(["meshes", 0, "primitives", 0, "mode"], 9))
    bad("points-only", set_(["meshes", 0, "primitives", 0, "mode"], 0))

    def sparse(indices, values=((5, 5, 5), (6, 6, 6))):
        def mutate_blob(blob):
            blob += struct.pack("<2I", *indices)
            for v in values:
                blob += struct.pack("<3f", *v)

        def mutate(doc):
            n = len(base()[1])
            doc["bufferViews"] += [{"buffer": 0, "byteOffset": n, "byteLength": 8},
                                   {"buffer": 0, "byteOffset": n + 8, "byteLength": 24}]
            doc["buffers"][0]["byteLength"] = n + 32
            doc["accessors"][0]["sparse"] = {"count": 2, "indices": {"bufferView": 2, "componentType": 5125},
                                             "values": {"bufferView": 3}}
        return mutate, mutate_blob

    bad("sparse-index-range", *sparse((1, 3)))
    bad("sparse-not-increasing", *sparse((2, 1)))

    for name, uri in [("uri-parent", "../outside.bin"), ("uri-absolute", "/etc/passwd"),
                      ("uri-encoded-parent", "sub/%2e%2e/%2E%2E/outside.bin")]:
        doc, blob = base()
        doc["buffers"][0]["uri"] = uri
        write_json(f"bad/{name}.gltf", doc)
    doc, blob = base()
    doc["buffers"][0]["uri"] = "missing.bin"
    write_json("bad/missing-bin.gltf", doc)

    for name, light, node_light in [
            ("light-index", {"type": "point"}, 3),
            ("light-cone", {"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.4}}, 0),
            ("light-intensity", {"type": "point", "intensity": -2.0}, 0),
            ("light-type", {"type": "area"}, 0)]:
        bad(name, with_lights([light], node_light))

    for name, kwargs in [("normal-type", {"accessor_type": "VEC2"}), ("normal-count", {"count": 2}),
                         ("normal-component", {"component": 5123})]:
        doc, blob = with_normals([(0.0, 0.0, 1.0)] * 3, **kwargs)
        write_json(f"bad/{name}.gltf", embed(doc, blob))
    doc, blob = with_normals([(0.0, 0.0, 1.0), (0.0, float("nan"), 1.0), (0.0, 0.0, 1.0)])
    write_json("bad/normal-nan.gltf", embed(doc, blob))

    def specular_colour(doc):
        doc["materials"][0]["extensions"] = {"KHR_materials_specular": {"specularColorFactor": [1, 1]}}
    bad("specular-colour", specular_colour)

    # glTF's metallic-roughness factors out of their ranges, KHR_materials_ior below 1 (other than 0)
    def material_with(pbr=None, extensions=None):
        def mutate(doc):
            if pbr:
                doc["materials"][0]["pbrMetallicRoughness"].update(pbr)
            if extensions:
                doc["materials"][0]["extensions"] = extensions
        return mutate
    bad("ior-below-one", material_with(extensions={"KHR_materials_ior": {"ior": 0.5}}))
    bad("metallic-negative", material_with(pbr={"metallicFactor": -0.25}))
    bad("specular-factor-range", material_with(extensions={"KHR_materials_specular": {"specularFactor": 1.5}}))
    bad("base-colour-negative", material_with(pbr={"baseColorFactor": [0.5, -0.1, 0.5, 1]}))


def furnace_file():
    """A closed unit box seen from its centre: every face emits Le = 1 and reflects Lambert albedo 0.5
    towards the inside, so every pixel reads Le / (1 - a) = 2 (the combination's furnace, issue #12)."""
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = []
    for a, b, c, d in faces:
        pa, pb, pc = corners[a], corners[b], corners[c]
        u = [pb[i] - pa[i] for i in range(3)]
        v = [pc[i] - pa[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        if sum(n[i] * -pa[i] for i in range(3)) < 0:  # front (counter-clockwise) towards the centre
            a, b, c, d = d, c, b, a
        indices += [a, b, c, a, c, d]
    doc, blob = base(corners, indices)
    doc["materials"] = [{"name": "furnace", "emissiveFactor": [1, 1, 1],
                         "extras": {"phong": {"kd": [0.5, 0.5, 0.5], "ks": [0, 0, 0], "shininess": 1}}}]
    doc["nodes"].append({"camera": 0})
    doc["scenes"][0]["nodes"] = [0, 1]
    doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 1.2, "znear": 0.01}}]
    write_json("good/furnace.gltf", embed(doc, blob))


if __name__ == "__main__":
    good_files()
    furnace_file()
    bad_files()
    texture_files()
    print("wrote", HERE)
