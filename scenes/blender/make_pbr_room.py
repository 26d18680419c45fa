# The "real materials" acceptance scene: make_room.py's 4 m x 4 m x 2.6 m room (a window in the
# left wall with the sun behind it, a point light under the ceiling) with Principled BSDF materials
# as a Blender user makes them, exported with Blender 5's glTF exporter to a .glb:
#
#   gold sphere      metallic 1, roughness 0.2
#   copper box       metallic 1, roughness 0.5
#   red plastic      Suzanne (one subdivision level), roughness 0.4
#   glazed ceramic   a blue torus, roughness 0.05
#   wood floor       roughness 0.35, a 128 x 64 plank texture generated here (sRGB PNG, embedded)
#   plaster wall     the back wall, roughness 0.9, a 128 x 128 tangent-space normal map generated
#                    here (Non-Color PNG, Normal Map node, strength 1)
#   white paint      the other walls and the ceiling, roughness 0.6
#   window pane      Transmission 1, IOR 1.5, roughness 0, no thickness: a thin-walled pane
#                    (KHR_materials_transmission; KHR_materials_ior with the default ior, which the
#                    exporter may write as an empty object or leave out: 1.5 either way)
#
# Run with bpy 5 as a module (the peers' venv):
#   /work/main/bench-out/peers-venv/bin/python scenes/blender/make_pbr_room.py OUT.glb [WIDTH HEIGHT]
# (default 320 x 180; only the camera's aspect depends on it: glTF stores yfov and the aspect).
# Exported with tangents (export_tangents: Blender's MikkTSpace TANGENT, which Cycles recomputes the
# same way on re-import), physical light units (a point light's W -> W/(4 pi) * 683 cd, the sun's
# W/m^2 -> 683 lux), the camera and the lights. The textures are written to a temporary folder and
# embedded in the .glb.
#
# It also prints the sunlit floor rectangle (SUNLIT_FLOOR below: inside the sun's patch through the
# window, clear of the objects' shadows) projected into the image, as fractions of width and height:
# bench/pbr_room.sh compares that patch alone.
import math
import os
import sys
import tempfile

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from room_rig import D, H, SUN_TRAVEL, W, WINDOW_Y, WINDOW_Z, add_lights_and_camera, mesh_object, quad  # noqa: E402

FLOOR_TEX = (128, 64)                    # wood texture, texels (u, v)
FLOOR_REPEAT = 2.0
NORMAL_TEX = 128                         # plaster normal map, texels a side
NORMAL_REPEAT = 2.0
# A floor rectangle (x0, x1, y0, y1) inside the sun's patch (the window seen along SUN_TRAVEL lands on
# x -0.8..0.67, y from -0.7 + 0.467 z to 0.7 + 0.467 z with z = 0.75 (x + 2)) and clear of the objects
# and their sun shadows.
SUNLIT_FLOOR = (-0.55, -0.05, 0.05, 0.5)


def args():
    rest = sys.argv[1:]
    if "--" in rest:
        rest = rest[rest.index("--") + 1:]
    if len(rest) not in (1, 3):
        raise SystemExit("usage: python scenes/blender/make_pbr_room.py OUT.glb [WIDTH HEIGHT]")
    width, height = (int(rest[1]), int(rest[2])) if len(rest) == 3 else (320, 180)
    return os.path.abspath(rest[0]), width, height


def principled(name, rgb, roughness, metallic=0.0, transmission=0.0, ior=1.5):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["IOR"].default_value = ior
    bsdf.inputs["Transmission Weight"].default_value = transmission
    mat.diffuse_color = (*rgb, 1.0)
    return mat, bsdf


def save_image(name, rgb, folder, colorspace):
    """rgb: (h, w, 3) floats in [0, 1], row 0 at the bottom (Blender's order). Saved as PNG."""
    h, w, _ = rgb.shape
    img = bpy.data.images.new(name, w, h, alpha=False)
    px = np.ones((h, w, 4), dtype=np.float32)
    px[:, :, :3] = rgb
    img.pixels.foreach_set(px.ravel())
    path = os.path.join(folder, name + ".png")
    img.filepath_raw = path
    img.file_format = 'PNG'
    img.save()
    img.source = 'FILE'
    img.filepath = path
    img.colorspace_settings.name = colorspace
    return img


def wood_texture(folder):
    """Planks along u (4 across v), each its own tone, with sinusoidal grain and dark joints."""
    w, h = FLOOR_TEX
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    uu, vv = np.meshgrid(u, v)
    plank = np.floor(vv * 4).astype(int)
    rng = np.random.default_rng(7)
    tone = rng.uniform(0.8, 1.15, size=4)[plank]
    offset = rng.uniform(0, 1, size=4)[plank]
    grain = 0.5 + 0.5 * np.sin(2 * np.pi * (uu * 6 + offset) + 3.0 * np.sin(2 * np.pi * vv * 8 + uu * 5))
    base = np.array([0.62, 0.40, 0.22])  # sRGB-encoded values
    dark = np.array([0.42, 0.25, 0.13])
    rgb = (base * (1 - grain[..., None]) + dark * grain[..., None]) * tone[..., None]
    joint = ((vv * 4) % 1.0 < 1.5 / (h / 4))  # one-texel seam between planks
    rgb[joint] = (0.2, 0.12, 0.07)
    return save_image("pbr-room-wood", np.clip(rgb, 0, 1), folder, 'sRGB')


def plaster_normal_map(folder):
    """A tangent-space normal map (OpenGL convention, +y up the texture, as glTF) of a periodic
    bumpy height field: a few random sine waves and round dimples."""
    n = NORMAL_TEX
    t = (np.arange(n) + 0.5) / n
    uu, vv = np.meshgrid(t, t)          # row 0 = v near 0 (Blender's bottom row)
    rng = np.random.default_rng(11)
    hgt = np.zeros((n, n))
    for _ in range(6):
        kx, ky = rng.integers(1, 6, size=2)
        hgt += rng.uniform(0.2, 1.0) / (kx + ky) * np.sin(2 * np.pi * (kx * uu + ky * vv) + rng.uniform(0, 6.3))
    for _ in range(12):                 # dimples, wrapped
        cx, cy, r = rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0.04, 0.09)
        dx = (uu - cx + 0.5) % 1.0 - 0.5
        dy = (vv - cy + 0.5) % 1.0 - 0.5
        hgt -= 0.6 * np.exp(-(dx * dx + dy * dy) / (r * r))
    strength = 0.08                     # height in units of the texture's width
    dhdu = (np.roll(hgt, -1, axis=1) - np.roll(hgt, 1, axis=1)) * n / 2 * strength
    dhdv = (np.roll(hgt, -1, axis=0) - np.roll(hgt, 1, axis=0)) * n / 2 * strength
    nrm = np.stack([-dhdu, -dhdv, np.ones_like(hgt)], axis=-1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    return save_image("pbr-room-plaster-normal", 0.5 * nrm + 0.5, folder, 'Non-Color')


def add_image(mat, image, socket, closest=False):
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = 'Closest' if closest else 'Linear'
    tex.extension = 'REPEAT'
    links.new(tex.outputs["Color"], socket)
    return tex


def smooth(obj, mat, subdivide=0):
    if subdivide:
        mod = obj.modifiers.new("subsurf", 'SUBSURF')
        mod.levels = subdivide
        mod.render_levels = subdivide
    for poly in obj.data.polygons:
        poly.use_smooth = True
    obj.data.materials.append(mat)


def build(width, height, folder):
    paint, _ = principled("white_paint", (0.8, 0.8, 0.78), 0.6)
    ceiling, _ = principled("ceiling_paint", (0.8, 0.8, 0.8), 0.6)
    plaster, plaster_bsdf = principled("plaster", (0.75, 0.72, 0.66), 0.9)
    nmap = plaster.node_tree.nodes.new("ShaderNodeNormalMap")
    nmap.space = 'TANGENT'
    nmap.uv_map = "UVMap"
    nmap.inputs["Strength"].default_value = 1.0
    add_image(plaster, plaster_normal_map(folder), nmap.inputs["Color"])
    plaster.node_tree.links.new(nmap.outputs["Normal"], plaster_bsdf.inputs["Normal"])
    wood, wood_bsdf = principled("wood_floor", (1.0, 1.0, 1.0), 0.35)
    add_image(wood, wood_texture(folder), wood_bsdf.inputs["Base Color"])
    gold, _ = principled("gold", (1.0, 0.766, 0.336), 0.2, metallic=1.0)
    copper, _ = principled("copper", (0.955, 0.638, 0.538), 0.5, metallic=1.0)
    plastic, _ = principled("red_plastic", (0.6, 0.04, 0.03), 0.4)
    ceramic, _ = principled("glazed_ceramic", (0.08, 0.22, 0.55), 0.05)
    glass, _ = principled("window_glass", (1.0, 1.0, 1.0), 0.0, transmission=1.0, ior=1.5)

    x0, x1, y0, y1 = -W / 2, W / 2, -D / 2, D / 2
    quad("floor", [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)], wood, (0, 0, 1),
         uv=lambda p: ((p[0] - x0) / W * FLOOR_REPEAT, (p[1] - y0) / D * FLOOR_REPEAT))
    quad("ceiling", [(x0, y0, H), (x0, y1, H), (x1, y1, H), (x1, y0, H)], ceiling, (0, 0, -1))
    quad("back_wall", [(x0, y1, 0), (x1, y1, 0), (x1, y1, H), (x0, y1, H)], plaster, (0, -1, 0),
         uv=lambda p: ((x1 - p[0]) / W * NORMAL_REPEAT, p[2] / W * NORMAL_REPEAT))
    quad("front_wall", [(x0, y0, 0), (x0, y0, H), (x1, y0, H), (x1, y0, 0)], paint, (0, 1, 0))
    quad("right_wall", [(x1, y0, 0), (x1, y0, H), (x1, y1, H), (x1, y1, 0)], paint, (-1, 0, 0))
    wy0, wy1 = WINDOW_Y
    wz0, wz1 = WINDOW_Z
    ys, zs = (y0, wy0, wy1, y1), (0.0, wz0, wz1, H)
    verts = [(x0, y, z) for z in zs for y in ys]
    cells = [(iy, iz) for iz in range(3) for iy in range(3) if (iy, iz) != (1, 1)]
    faces = [(4 * iz + iy, 4 * iz + iy + 1, 4 * (iz + 1) + iy + 1, 4 * (iz + 1) + iy) for iy, iz in cells]
    left = mesh_object("left_wall_window", verts, faces, paint)
    for poly in left.data.polygons:
        assert poly.normal.dot(Vector((1, 0, 0))) > 0.99, ("left wall", poly.index, tuple(poly.normal))
    quad("window_pane", [(x0, wy0, wz0), (x0, wy1, wz0), (x0, wy1, wz1), (x0, wy0, wz1)], glass, (1, 0, 0))

    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.4, location=(0.75, 0.75, 0.4))
    sphere = bpy.context.active_object
    sphere.name = "gold_sphere"
    smooth(sphere, gold)
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(1.2, -0.3, 0.3), rotation=(0, 0, math.radians(25)))
    box = bpy.context.active_object
    box.name = "copper_box"
    box.data.materials.append(copper)
    bpy.ops.mesh.primitive_monkey_add(size=0.8, location=(-0.9, 1.2, 0.5), rotation=(0, 0, math.radians(20)))
    monkey = bpy.context.active_object
    monkey.name = "red_plastic_suzanne"
    smooth(monkey, plastic, subdivide=1)
    bpy.ops.mesh.primitive_torus_add(major_radius=0.28, minor_radius=0.1, major_segments=32, minor_segments=12,
                                     location=(0.25, 1.35, 0.1))
    torus = bpy.context.active_object
    torus.name = "glazed_ceramic_torus"
    smooth(torus, ceramic)

    scene, cam_obj = add_lights_and_camera(width, height, (1.5, -1.8, 1.6), (-0.4, 0.7, 0.5))
    return scene, cam_obj


def sunlit_patch(scene, cam_obj):
    """The SUNLIT_FLOOR rectangle's bounding box in the image, as fractions (left, top, right, bottom)."""
    bpy.context.view_layer.update()
    xa, xb, ya, yb = SUNLIT_FLOOR
    pts = [world_to_camera_view(scene, cam_obj, Vector((x, y, 0.0))) for x in (xa, xb) for y in (ya, yb)]
    return (min(p.x for p in pts), 1 - max(p.y for p in pts), max(p.x for p in pts), 1 - min(p.y for p in pts))


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
        export_tangents=True,
        export_materials='EXPORT',
        export_image_format='AUTO',
        export_animations=False,
        export_extras=False,
    )


def main():
    path, width, height = args()
    folder = tempfile.mkdtemp(prefix="pbr-room-textures-")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene, cam_obj = build(width, height, folder)
    patch = sunlit_patch(scene, cam_obj)
    export(path)
    print("SUNLIT_PATCH %.4f %.4f %.4f %.4f" % patch)
    print("wrote", path, os.path.getsize(path), "bytes")


main()
