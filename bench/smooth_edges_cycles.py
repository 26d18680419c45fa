"""Renders one camera of the smooth-edges scene (scenes/blender/make_smooth_edges.py) with Blender
Cycles 5 (bpy 5.0.1 as a module), the reference of bench/smooth_edges.sh. Runs in the peers' venv:

  /work/main/bench-out/peers-venv/bin/python bench/smooth_edges_cycles.py SCENE.glb OUT_PREFIX \
      --camera NAME --world R,G,B --width W --height H --spp N [--seed K] [--threads T]
      [--geometry-offset X]

Writes OUT_PREFIX.exr (linear RGBA float, 32 bit) and OUT_PREFIX.json (spp, seed, Cycles' sampling
time, wall).

The file is re-imported with Blender's glTF importer (physical light units, the exporter's inverse:
lux / 683 -> the sun's W/m^2; import_shading NORMALS: the file's normals become the mesh's custom
normals, so Cycles interpolates the same vertex normals bundlepath reads). Then:
* materials: kept as imported (a Principled BSDF); each must have metallic 0 and Specular IOR Level 0
  (the file's specularFactor 0) and nothing else lit: pure Lambert in Cycles (no specular layer,
  Diffuse Roughness 0), as glTF's BRDF is with specularFactor 0; the script stops otherwise;
* lights: sun angle 0 (the importer sets Blender's default 0.526 degrees; glTF's is a parallel
  light), radius 0 and soft falloff off for any other;
* world: a uniform Background of colour R,G,B at strength 1: radiance R,G,B W sr^-1 m^-2, as
  bundlepath's `--environment R,G,B` (seen by camera rays and lighting the scene);
* camera: the camera object named NAME (the glTF node's name), sensor fit vertical with the file's
  yfov (the aspect ratio follows W x H, as bundlepath's does);
* shadow-terminator offsets: shading and normal offsets 0, geometry offset X (default 0; Blender's
  default is 0.1). In Blender 5 these are the Object's own properties
  (Object.shadow_terminator_geometry_offset, ..._shading_offset, ..._normal_offset); the
  obj.cycles.shadow_terminator_* names the older scripts set are leftovers Cycles does not read, so
  they leave the geometry offset at 0.1. At 0.1 a shadow ray leaves from the smooth (Phong-
  tessellated) surface: a smooth face whose flat normal is turned from the sun while its
  interpolated normal faces it sees the sun (here: a bright triangle at the top of the cylinder's
  side, the upper left in cylinder_15), where the flat surface shadows itself at 0;
* Cycles' settings: bench/peers/cycles_peer.py's render_settings (CPU, light tree on, no adaptive
  sampling, no denoiser, no clamping, no light threshold, no glossy filter, 1024 bounces of every
  kind, a 1-pixel box filter, view transform Standard).
Cycles keeps interpolated normals that face away from the viewer usable: its closures' normal goes
through ensure_valid_specular_reflection (the normal is bent towards the geometric one until the
mirror direction of the view is above the surface), so a smooth rim is shaded, not black.
"""
import argparse
import json
import math
import os
import struct
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "peers"))
import cycles_peer  # noqa: E402  (its main() runs only as a script)

import bpy  # noqa: E402


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("--camera", required=True)
    p.add_argument("--world", required=True, help="R,G,B: the Background's radiance, W sr^-1 m^-2")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--spp", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--geometry-offset", type=float, default=0.0,
                   help="Object.shadow_terminator_geometry_offset of every mesh (Blender's default: 0.1)")
    a = p.parse_args()
    a.world = tuple(float(v) for v in a.world.split(","))
    if len(a.world) != 3:
        p.error("--world needs R,G,B")
    return a


def gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        return json.loads(data.decode("utf-8"))
    n = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + n].decode("utf-8"))


def check_lambert(mat):
    """The imported material is Lambert in Cycles (module docstring), or the script stops."""
    bsdf = next((n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
    if bsdf is None:
        raise SystemExit("smooth_edges_cycles: material %r has no Principled BSDF" % mat.name)
    inp = bsdf.inputs
    values = {k: inp[k].default_value for k in ("Metallic", "Specular IOR Level", "Diffuse Roughness",
                                                 "Coat Weight", "Sheen Weight", "Transmission Weight",
                                                 "Subsurface Weight", "Emission Strength")}
    linked = [k for k in values if inp[k].is_linked]
    if linked or any(v != 0.0 for v in values.values()):
        raise SystemExit("smooth_edges_cycles: material %r is not plain Lambert: %s (linked: %s)"
                         % (mat.name, values, linked))
    print("smooth_edges_cycles: %s: Lambert, base colour %s" % (
        mat.name, tuple(round(c, 4) for c in inp["Base Color"].default_value[:3])))


def main():
    a = parse_args()
    t0 = time.perf_counter()
    scene_path = os.path.abspath(a.scene)
    gltf = gltf_json(scene_path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=scene_path, export_import_convert_lighting_mode='SPEC',
                              import_shading='NORMALS')
    s = bpy.context.scene
    for mat in bpy.data.materials:
        if mat.node_tree is not None:
            check_lambert(mat)
    for light in bpy.data.lights:
        light.shadow_soft_size = 0.0
        if hasattr(light, "use_soft_falloff"):
            light.use_soft_falloff = False
        if light.type == 'SUN':
            light.angle = 0.0
        print("smooth_edges_cycles: light %s %s energy %.6g colour %s" % (light.name, light.type, light.energy,
                                                                          tuple(light.color)))
    for obj in s.objects:
        if obj.type == 'MESH':
            # Blender 5's settings are the Object's own (obj.cycles.shadow_terminator_* are leftovers
            # that Cycles no longer reads); the geometry offset is 0.1 by default
            obj.shadow_terminator_geometry_offset = a.geometry_offset
            obj.shadow_terminator_shading_offset = 0.0
            obj.shadow_terminator_normal_offset = 0.0
    cam_obj = s.objects.get(a.camera)
    if cam_obj is None or cam_obj.type != 'CAMERA':
        raise SystemExit("smooth_edges_cycles: no camera object %r (have %s)" % (
            a.camera, [o.name for o in s.objects if o.type == 'CAMERA']))
    node = next(n for n in gltf["nodes"] if n.get("name") == a.camera and "camera" in n)
    yfov = gltf["cameras"][node["camera"]]["perspective"]["yfov"]
    s.camera = cam_obj
    cam = cam_obj.data
    cam.sensor_fit = 'VERTICAL'
    cam.sensor_height = 24.0
    cam.lens = 12.0 / math.tan(0.5 * yfov)
    cam.clip_start = 1e-3
    cam.clip_end = 1e4
    print("smooth_edges_cycles: camera %s yfov %.6f (angle_y %.6f)" % (cam_obj.name, yfov, cam.angle_y))
    world = bpy.data.worlds.new("uniform")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*a.world, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    s.world = world
    cycles_peer.render_settings(s, a.width, a.height, a.out + ".exr", spp=a.spp, seed=a.seed, threads=a.threads)
    t1 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    t2 = time.perf_counter()
    reported = cycles_peer.cycles_render_seconds(a.out + ".exr")
    result = {"renderer": "Cycles " + bpy.app.version_string, "camera": a.camera, "spp": a.spp, "seed": a.seed,
              "world": a.world, "threads": a.threads,
              "render_seconds": reported if reported is not None else t2 - t1, "wall_seconds": t2 - t0}
    with open(a.out + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print("smooth_edges_cycles:", json.dumps(result))


main()
