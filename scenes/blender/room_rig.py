# The room's meshes' helpers, lights and camera, shared by make_room.py (Blender 3.4) and make_pbr_room.py (Blender 5):
# the same sun through the window, point light under the ceiling and perspective camera in both.
import math

import bpy
from mathutils import Vector

W, D, H = 4.0, 4.0, 2.6                  # room: x -2..2, y -2..2, z 0..2.6 (Blender is z up)
WINDOW_Y = (-0.7, 0.7)                   # window opening in the left wall (x = -2)
WINDOW_Z = (0.9, 2.0)
SUN_STRENGTH = 20.0                      # W/m^2 (Blender sun strength; exported as 683 * 20 lux)
SUN_TRAVEL = Vector((1.0, 0.35, -0.75))  # the direction sunlight travels: in through the window, down
POINT_WATTS = 100.0                      # Blender point-light power (exported as W/(4 pi) * 683 cd)
POINT_POS = (0.9, -0.6, 2.3)


def add_lights_and_camera(width, height, camera_at, look_at):
    """The sun (angle 0), the point light (radius 0) and a 55-degree vertical-FOV camera at camera_at
    looking at look_at; the scene's camera and resolution set. Returns (scene, camera object)."""
    sun = bpy.data.lights.new("sun", type='SUN')
    sun.energy = SUN_STRENGTH
    sun.angle = 0.0
    sun_obj = bpy.data.objects.new("sun", sun)
    sun_obj.location = (-4.0, -1.0, 4.0)
    sun_obj.rotation_euler = SUN_TRAVEL.normalized().to_track_quat('-Z', 'Y').to_euler()
    bpy.context.scene.collection.objects.link(sun_obj)

    point = bpy.data.lights.new("point", type='POINT')
    point.energy = POINT_WATTS
    point.shadow_soft_size = 0.0
    point_obj = bpy.data.objects.new("point", point)
    point_obj.location = POINT_POS
    bpy.context.scene.collection.objects.link(point_obj)

    cam = bpy.data.cameras.new("camera")
    cam.type = 'PERSP'
    cam.sensor_fit = 'VERTICAL'
    cam.angle_y = math.radians(55.0)
    cam.clip_start = 0.05
    cam.clip_end = 100.0
    cam_obj = bpy.data.objects.new("camera", cam)
    cam_obj.location = camera_at
    look = Vector(look_at) - cam_obj.location
    cam_obj.rotation_euler = look.to_track_quat('-Z', 'Y').to_euler()
    bpy.context.scene.collection.objects.link(cam_obj)
    scene = bpy.context.scene
    scene.camera = cam_obj
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    return scene, cam_obj


def mesh_object(name, verts, faces, mat, uv=None):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    if uv is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        for loop in mesh.loops:
            layer.data[loop.index].uv = uv(verts[loop.vertex_index])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def quad(name, verts, mat, facing, uv=None):
    """One quad, counter-clockwise seen from its front; asserts that the front faces `facing`."""
    obj = mesh_object(name, verts, [(0, 1, 2, 3)], mat, uv)
    normal = obj.data.polygons[0].normal
    assert normal.dot(Vector(facing)) > 0.99, (name, tuple(normal), facing)
    return obj
