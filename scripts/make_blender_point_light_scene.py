# Builds a 2 m Cornell-like room (red left, green right, open front, two boxes) lit by one 100 W Blender POINT light, plus a camera,
# and exports it with Blender's glTF exporter as glTF embedded with KHR_lights_punctual (the exporter turns W into cd).
# Regenerate: blender --background --factory-startup --python scripts/make_blender_point_light_scene.py -- scenes/blender-point-light.gltf
import math
import os
import sys

import bpy
from mathutils import Vector

ROOM = 2.0            # metres; the room spans x -1..1, y -1..1 (front open at y = -1), z 0..2 (Blender is z up)
LIGHT_WATTS = 100.0   # Blender point-light power
LIGHT_POS = (0.0, 0.0, 1.9)  # 10 cm below the ceiling, centre


def out_path():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 1:
        raise SystemExit("usage: blender --background --factory-startup --python "
                         "scripts/make_blender_point_light_scene.py -- OUT.gltf")
    return os.path.abspath(args[0])


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights):
        for block in list(coll):
            coll.remove(block)


def diffuse(name, rgb):
    """Principled BSDF with only a base colour: roughness 1, metallic 0, specular 0."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Specular"].default_value = 0.0
    mat.diffuse_color = (*rgb, 1.0)
    return mat


def quad(name, verts, mat, facing):
    """One quad (verts counter-clockwise seen from its front); checks the front faces `facing`."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], [(0, 1, 2, 3)])
    mesh.update()
    normal = mesh.polygons[0].normal
    assert normal.dot(Vector(facing)) > 0.99, (name, tuple(normal), facing)
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def box(name, size, centre, rot_z_deg, mat):
    """An axis-aligned box (faces out), placed by the object transform (exported as node TRS)."""
    sx, sy, sz = (s / 2 for s in size)
    verts = [(-sx, -sy, -sz), (sx, -sy, -sz), (sx, sy, -sz), (-sx, sy, -sz),
             (-sx, -sy, sz), (sx, -sy, sz), (sx, sy, sz), (-sx, sy, sz)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    for poly in mesh.polygons:  # every face must point away from the box centre (the origin)
        assert poly.normal.dot(poly.center) > 0, (name, poly.index)
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = centre
    obj.rotation_euler = (0.0, 0.0, math.radians(rot_z_deg))
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build():
    white = diffuse("white", (0.73, 0.73, 0.73))
    red = diffuse("red", (0.63, 0.065, 0.05))
    green = diffuse("green", (0.14, 0.45, 0.091))
    h = ROOM / 2
    t = ROOM
    quad("floor", [(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], white, (0, 0, 1))
    quad("ceiling", [(-h, -h, t), (-h, h, t), (h, h, t), (h, -h, t)], white, (0, 0, -1))
    quad("back_wall", [(-h, h, 0), (h, h, 0), (h, h, t), (-h, h, t)], white, (0, -1, 0))
    quad("left_wall", [(-h, -h, 0), (-h, h, 0), (-h, h, t), (-h, -h, t)], red, (1, 0, 0))
    quad("right_wall", [(h, -h, 0), (h, -h, t), (h, h, t), (h, h, 0)], green, (-1, 0, 0))
    box("short_box", (0.6, 0.6, 0.6), (0.35, -0.3, 0.3), -17.0, white)
    box("tall_box", (0.6, 0.6, 1.2), (-0.35, 0.3, 0.6), 17.0, white)

    light = bpy.data.lights.new("point_light", type='POINT')
    light.energy = LIGHT_WATTS
    light.color = (1.0, 1.0, 1.0)
    light.shadow_soft_size = 0.0
    light_obj = bpy.data.objects.new("point_light", light)
    light_obj.location = LIGHT_POS
    bpy.context.scene.collection.objects.link(light_obj)

    cam = bpy.data.cameras.new("camera")
    cam.type = 'PERSP'
    cam.sensor_fit = 'VERTICAL'
    cam.angle = math.radians(39.3)
    cam.clip_start = 0.1
    cam.clip_end = 100.0
    cam_obj = bpy.data.objects.new("camera", cam)
    cam_obj.location = (0.0, -3.9, 1.0)            # outside the open front, eye at mid height
    cam_obj.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # looks along +y, into the room
    bpy.context.scene.collection.objects.link(cam_obj)
    scene = bpy.context.scene
    scene.camera = cam_obj
    scene.render.resolution_x = 512
    scene.render.resolution_y = 512
    scene.unit_settings.system = 'METRIC'
    scene.unit_settings.scale_length = 1.0


def export(path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bpy.ops.export_scene.gltf(
        filepath=path,
        export_format='GLTF_EMBEDDED',
        export_lights=True,               # KHR_lights_punctual
        convert_lighting_mode='SPEC',     # physical units: point W -> cd = W / (4 pi) * 683
        export_cameras=True,
        export_apply=True,
        export_yup=True,
        export_texcoords=False,
        export_normals=True,
        export_materials='EXPORT',
        export_animations=False,
        export_extras=False,
    )


def main():
    path = out_path()
    clear_scene()
    build()
    export(path)
    print("wrote", path, os.path.getsize(path), "bytes")


main()
