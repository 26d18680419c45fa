#!/usr/bin/env python3
"""Control variants of scenes/blender-pbr-room.glb for bench/pbr_room.sh's diagnosis (standard
library only; rewrites the .glb's JSON chunk, the binary chunk kept):

  python3 bench/pbr_room_variant.py IN.glb OUT.glb [--lambert-room] [--lambert-objects] [--nearest]
                                     [--flat MESH,...] [--no-light NODE]

--lambert-room: the paints, the plaster and the wood floor get KHR_materials_specular
  specularFactor 0 (bundlepath: pure Lambert; Blender's importer: Specular IOR Level 0, Principled
  without a specular layer), which takes glTF's and Blender's different dielectric layering out of
  the room's large surfaces; the objects and the pane stay as they are.
--lambert-objects: the same for the red plastic and the glazed ceramic, so that with --lambert-room
  every dielectric is Lambert and only the metals and the pane keep a specular lobe (glTF's Schlick
  Fresnel and Blender's exact one differ most on a dielectric's glare).
--nearest: every sampler NEAREST (Cycles: Closest), which takes the order of sRGB decoding and
  bilinear filtering out of the floor texture.
--flat MESH,...: the named meshes lose their NORMAL and TANGENT attributes, so both renderers shade
  them flat (glTF: flat normals where none are given), which takes the shading normals' treatment
  at silhouettes out (e.g. --flat Sphere,Mesh: the gold sphere and the Suzanne).
--no-light NODE: the node named NODE (e.g. sun) no longer carries its KHR_lights_punctual light.
Then render OUT.glb as bench/pbr_room.sh does (bundlepath render ..., scenes/blender/cycles_pbr_render.py).
"""
import argparse
import json
import struct

LAMBERT = ("white_paint", "ceiling_paint", "plaster", "wood_floor")
LAMBERT_OBJECTS = ("red_plastic", "glazed_ceramic")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("src")
    p.add_argument("dst")
    p.add_argument("--lambert-room", action="store_true")
    p.add_argument("--lambert-objects", action="store_true")
    p.add_argument("--nearest", action="store_true")
    p.add_argument("--flat", default="")
    p.add_argument("--no-light", default="")
    a = p.parse_args()
    data = open(a.src, "rb").read()
    n = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20:20 + n])
    rest = data[20 + n:]
    lambert = (LAMBERT if a.lambert_room else ()) + (LAMBERT_OBJECTS if a.lambert_objects else ())
    if lambert:
        for m in gltf["materials"]:
            if m["name"] in lambert:
                m.setdefault("extensions", {})["KHR_materials_specular"] = {"specularFactor": 0.0}
        gltf["extensionsUsed"] = sorted(set(gltf.get("extensionsUsed", [])) | {"KHR_materials_specular"})
    flat = set(filter(None, a.flat.split(",")))
    unknown = flat - {m["name"] for m in gltf["meshes"]}
    if unknown:
        raise SystemExit("pbr_room_variant.py: no mesh named %s" % ", ".join(sorted(unknown)))
    for m in gltf["meshes"]:
        if m["name"] in flat:
            for prim in m["primitives"]:
                prim["attributes"].pop("NORMAL", None)
                prim["attributes"].pop("TANGENT", None)
    if a.no_light:
        lit = [nd for nd in gltf["nodes"] if nd.get("name") == a.no_light and "KHR_lights_punctual" in nd.get("extensions", {})]
        if not lit:
            raise SystemExit("pbr_room_variant.py: no node named %s carries a light" % a.no_light)
        for nd in lit:
            del nd["extensions"]["KHR_lights_punctual"]
    if a.nearest:
        for s in gltf.get("samplers", []):
            s["magFilter"] = 9728
            s["minFilter"] = 9728
    j = json.dumps(gltf, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    with open(a.dst, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 20 + len(j) + len(rest)) + struct.pack("<II", len(j), 0x4E4F534A)
                + j + rest)


if __name__ == "__main__":
    main()
