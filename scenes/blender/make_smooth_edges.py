# The "smooth edges" scene: smooth-shaded meshes as a Blender user makes them, whose interpolated
# shading normals face away from the viewer near rims and silhouettes while the geometric normal
# faces it, exported with Blender 5's own glTF exporter to a .glb. bench/smooth_edges.sh renders it
# with bundlepath and with Cycles 5 (bench/smooth_edges_cycles.py) and compares.
#
#   floor      a 100 m x 100 m plane at z = 0, grey 0.5 (flat)
#   cylinder   Blender's default cylinder primitive (32 vertices, radius 1, depth 2, capped with an
#              n-gon), Shade Smooth (every face smooth, no sharp edges, NOT smooth-by-angle): the
#              rim vertices carry the average of the cap's and the side's normals (about 45 degrees
#              up), so the whole cap is shaded with normals tilted outwards; blue 0.1, 0.2, 0.8
#   torus      Blender's default torus (48 x 12 segments, radii 1 and 0.25), Shade Smooth; orange
#              0.8, 0.35, 0.05
#   suzanne    Suzanne (size 2), Subdivision Surface level 2 (applied by the exporter), Shade
#              Smooth; green 0.2, 0.7, 0.2
#
# Every material is a Principled BSDF that is plain diffuse the way glTF and Principled agree:
# metallic 0, roughness 1, Specular IOR Level 0 (exported as KHR_materials_specular
# specularFactor 0: glTF's BRDF is then pure Lambert; Blender's importer maps it back to Specular
# IOR Level 0: no specular layer at all, Lambert too: "Diffuse Roughness" stays 0).
#
# Light:
#   * one sun of SUN_STRENGTH W/m^2 (Blender's sun strength = irradiance on a surface facing it),
#     angle 0 (glTF's directional light is a parallel light; the exporter writes no angle, and
#     Blender's importer gives it Blender's default 0.526 degrees, which bench/smooth_edges_cycles.py
#     sets back to 0); exported with Punctual Lights in physical units: SUN_STRENGTH * 683 lux,
#     which bundlepath reads back at 683 lm/W;
#   * a uniform grey world of radiance WORLD (W sr^-1 m^-2, linear RGB: Cycles' Background colour
#     at strength 1). glTF has no world and the exporter writes none: bundlepath gets it as
#     `--environment WORLD` and bench/smooth_edges_cycles.py sets the same Background.
#   This script prints both on the line "LIGHT sun W/m^2 world R,G,B" for bench/smooth_edges.sh.
#
# Cameras (perspective, sensor fit VERTICAL, so the exported yfov is the one set here; the aspect
# ratio is the render resolution's, 320 x 180 unless given): each named object is a glTF camera
# node of the same name, which `bundlepath render --camera NAME` picks and Blender's importer
# re-creates as an object of that name. Elevation is the angle of the line of sight above the
# floor, looking at the target:
#   group_10     all three at 10 degrees (rims and silhouettes edge-on)
#   group_25     all three at 25 degrees
#   group_45     all three at 45 degrees
#   cylinder_15  the cylinder alone, close, at 15 degrees (its cap's far rim, a band in the image)
#   suzanne_20   Suzanne alone, close, at 20 degrees
# The script prints "CAMERA name" for each, in the file's order.
#
# Run with bpy 5 as a module (the peers' venv):
#   /work/main/bench-out/peers-venv/bin/python scenes/blender/make_smooth_edges.py OUT.glb [WIDTH HEIGHT]
# Exported with normals (export_normals: the averaged rim normals are the point), modifiers applied,
# +Y up, cameras, punctual lights (export_import_convert_lighting_mode SPEC), no tangents, no
# textures. The script checks the exported file: the cylinder's cap normals must be tilted (the
# smoothing was applied) and the materials must carry specularFactor 0.
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Vector

SUN_STRENGTH = 3.0                    # W/m^2 (Blender's sun strength; exported as 683 * 3 = 2049 lux)
SUN_ELEVATION = 40.0                  # degrees above the horizon
SUN_AZIMUTH = 150.0                   # degrees: where the sun is, from +x towards +y (behind-left of the cameras)
WORLD = (0.25, 0.25, 0.25)            # W sr^-1 m^-2: bundlepath --environment 0.25,0.25,0.25
FLOOR_SIZE = 100.0
YFOV_GROUP = 40.0                     # degrees, vertical
YFOV_CLOSE = 30.0

OBJECTS = {                           # name: (location, colour)
    "cylinder": ((0.0, 0.0, 1.0), (0.1, 0.2, 0.8)),
    "torus": ((3.2, 1.0, 0.25), (0.8, 0.35, 0.05)),
    "suzanne": ((-3.2, 0.5, 1.0), (0.2, 0.7, 0.2)),
}
FLOOR_COLOUR = (0.5, 0.5, 0.5)

# name: (target, elevation deg, azimuth deg of the camera around the target from +x towards +y,
#        distance m, yfov deg)
CAMERAS = {
    "group_10": ((0.0, 0.5, 0.8), 10.0, -90.0, 9.0, YFOV_GROUP),
    "group_25": ((0.0, 0.5, 0.8), 25.0, -80.0, 9.0, YFOV_GROUP),
    "group_45": ((0.0, 0.5, 0.6), 45.0, -100.0, 9.0, YFOV_GROUP),
    "cylinder_15": ((0.0, 0.0, 1.3), 15.0, -70.0, 5.0, YFOV_CLOSE),
    "suzanne_20": ((-3.2, 0.5, 1.0), 20.0, -110.0, 4.5, YFOV_CLOSE),
}


def args():
    rest = sys.argv[1:]
    if "--" in rest:
        rest = rest[rest.index("--") + 1:]
    if len(rest) not in (1, 3):
        raise SystemExit("usage: python scenes/blender/make_smooth_edges.py OUT.glb [WIDTH HEIGHT]")
    width, height = (int(rest[1]), int(rest[2])) if len(rest) == 3 else (320, 180)
    return os.path.abspath(rest[0]), width, height


def diffuse(name, rgb):
    """A Principled BSDF that is Lambert in glTF and in Cycles (module docstring)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Specular IOR Level"].default_value = 0.0
    mat.diffuse_color = (*rgb, 1.0)
    return mat


def smooth(obj, mat):
    """Shade Smooth: every face smooth, no edge kept sharp (not smooth-by-angle)."""
    bpy.ops.object.select_all(action='DESELECT')
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.shade_smooth(keep_sharp_edges=False)
    assert all(p.use_smooth for p in obj.data.polygons), obj.name
    obj.data.materials.append(mat)


def build(width, height):
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=FLOOR_SIZE, location=(0.0, 0.0, 0.0))
    floor = bpy.context.active_object
    floor.name = "floor"
    floor.data.materials.append(diffuse("floor_grey", FLOOR_COLOUR))

    loc, col = OBJECTS["cylinder"]
    bpy.ops.mesh.primitive_cylinder_add(vertices=32, radius=1.0, depth=2.0, end_fill_type='NGON', location=loc)
    cyl = bpy.context.active_object
    cyl.name = "cylinder"
    smooth(cyl, diffuse("cylinder_blue", col))

    loc, col = OBJECTS["torus"]
    bpy.ops.mesh.primitive_torus_add(location=loc)
    torus = bpy.context.active_object
    torus.name = "torus"
    smooth(torus, diffuse("torus_orange", col))

    loc, col = OBJECTS["suzanne"]
    bpy.ops.mesh.primitive_monkey_add(size=2.0, location=loc, rotation=(0.0, 0.0, math.radians(-20.0)))
    monkey = bpy.context.active_object
    monkey.name = "suzanne"
    mod = monkey.modifiers.new("subsurf", 'SUBSURF')
    mod.levels = 2
    mod.render_levels = 2
    smooth(monkey, diffuse("suzanne_green", col))

    sun = bpy.data.lights.new("sun", type='SUN')
    sun.energy = SUN_STRENGTH
    sun.angle = 0.0
    sun_obj = bpy.data.objects.new("sun", sun)
    el, az = math.radians(SUN_ELEVATION), math.radians(SUN_AZIMUTH)
    towards_sun = Vector((math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)))
    sun_obj.location = 20.0 * towards_sun
    sun_obj.rotation_euler = (-towards_sun).to_track_quat('-Z', 'Y').to_euler()
    scene.collection.objects.link(sun_obj)

    for name, (target, elev, azim, dist, yfov) in CAMERAS.items():
        cam = bpy.data.cameras.new(name)
        cam.type = 'PERSP'
        cam.sensor_fit = 'VERTICAL'
        cam.angle_y = math.radians(yfov)
        cam.clip_start = 0.05
        cam.clip_end = 500.0
        obj = bpy.data.objects.new(name, cam)
        e, a = math.radians(elev), math.radians(azim)
        offset = Vector((math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e))) * dist
        obj.location = Vector(target) + offset
        obj.rotation_euler = (-offset).to_track_quat('-Z', 'Y').to_euler()
        scene.collection.objects.link(obj)
    scene.camera = bpy.data.objects[next(iter(CAMERAS))]
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100


def export(path):
    bpy.ops.export_scene.gltf(
        filepath=path,
        export_format='GLB',
        export_lights=True,
        export_import_convert_lighting_mode='SPEC',
        export_cameras=True,
        export_apply=True,
        export_yup=True,
        export_texcoords=True,
        export_normals=True,
        export_tangents=False,
        export_materials='EXPORT',
        export_animations=False,
        export_extras=False,
    )


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + n].decode("utf-8"))
    m = struct.unpack_from("<I", data, 20 + n)[0]
    return doc, data[28 + n:28 + n + m]


def accessor_vec3(doc, binary, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    assert acc["componentType"] == 5126 and acc["type"] == "VEC3", acc
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 12)
    return [struct.unpack_from("<3f", binary, start + i * stride) for i in range(acc["count"])]


def check(path):
    """The exported file holds what the bench relies on (module docstring); prints a summary."""
    doc, binary = read_glb(path)
    for mat in doc["materials"]:
        spec = mat.get("extensions", {}).get("KHR_materials_specular", {})
        pbr = mat.get("pbrMetallicRoughness", {})
        print("MATERIAL %s base %s metallic %s roughness %s specularFactor %s" % (
            mat["name"], pbr.get("baseColorFactor"), pbr.get("metallicFactor", 1.0),
            pbr.get("roughnessFactor", 1.0), spec.get("specularFactor", 1.0)))
        if spec.get("specularFactor", 1.0) != 0.0:
            raise SystemExit("make_smooth_edges: %s exported without specularFactor 0" % mat["name"])
    by_name = {n.get("name"): n for n in doc["nodes"]}
    cyl = doc["meshes"][by_name["cylinder"]["mesh"]]
    prim = cyl["primitives"][0]
    pos = accessor_vec3(doc, binary, prim["attributes"]["POSITION"])
    nrm = accessor_vec3(doc, binary, prim["attributes"]["NORMAL"])
    # +Y up in the file; the cylinder's own frame (the node translates it by 1 up): top cap at y = 1
    cap = [n for p, n in zip(pos, nrm) if p[1] > 0.99]
    ups = sorted(n[1] for n in cap)
    print("CYLINDER %d vertices, %d at the top rim, their normals' up component %.3f..%.3f" % (
        len(pos), len(cap), ups[0], ups[-1]))
    if not cap or ups[-1] > 0.95 or ups[0] < 0.3:
        raise SystemExit("make_smooth_edges: the cylinder's rim normals are not averaged (Shade Smooth lost?)")
    cams = [n["name"] for n in doc["nodes"] if "camera" in n]
    for name in cams:
        c = doc["cameras"][by_name[name]["camera"]]["perspective"]
        print("CAMERA %s yfov %.4f deg aspect %.4f" % (name, math.degrees(c["yfov"]), c.get("aspectRatio", 0.0)))
    for light in doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", []):
        print("GLTF_LIGHT %s %s intensity %.6g (%.6g W/m^2 at 683 lm/W)" % (
            light.get("name"), light["type"], light["intensity"], light["intensity"] / 683.0))


def main():
    path, width, height = args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build(width, height)
    export(path)
    check(path)
    print("LIGHT sun %g W/m^2 world %g,%g,%g" % (SUN_STRENGTH, *WORLD))
    print("wrote", path, os.path.getsize(path), "bytes")


main()
