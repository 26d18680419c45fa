# Builds a closed 4 m x 4 m x 2.6 m room with one window in its left wall, a sun shining through
# the window onto the floor, a point light under the ceiling, an image-textured (tiled) floor, two
# smooth-shaded objects (a subdivided UV sphere and a subdivided Suzanne) and a camera, then exports
# it with Blender's own glTF exporter as .glb (KHR_lights_punctual, physical light units).
#
# Run (Debian 12's Blender 3.4):
#   blender -b --factory-startup --python scenes/blender/make_room.py -- OUT.glb [WIDTH HEIGHT]
# The floor texture is generated here (a 64x64 tile pattern) and written next to OUT as
# OUT_dir/blender-room-floor.png; the .glb embeds it. Every material is a Principled BSDF with
# Specular 0, Roughness 1, Metallic 0: our loader reads that as pure Lambert (specularColorFactor
# [0,0,0]), and bench/blender_compare.sh renders the same file in Cycles with Diffuse BSDFs.
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from room_rig import D, H, W, WINDOW_Y, WINDOW_Z, add_lights_and_camera, mesh_object, quad  # noqa: E402

TEX_SIZE = 64                            # texels per side of the floor texture
TEX_REPEAT = 2.0                         # the texture repeats twice across the floor


def args():
    argv = sys.argv
    rest = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(rest) not in (1, 3):
        raise SystemExit("usage: blender -b --factory-startup --python scenes/blender/make_room.py -- OUT.glb [WIDTH HEIGHT]")
    width, height = (int(rest[1]), int(rest[2])) if len(rest) == 3 else (160, 120)
    return os.path.abspath(rest[0]), width, height


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights, bpy.data.images):
        for block in list(coll):
            coll.remove(block)


def lambert(name, rgb, image=None):
    """Principled BSDF that both renderers read as Lambert: roughness 1, metallic 0, specular 0.
    With `image`, an Image Texture node (sRGB, Closest: glTF NEAREST) feeds Base Color."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Specular"].default_value = 0.0
    mat.diffuse_color = (*rgb, 1.0)
    if image is not None:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = image
        tex.interpolation = 'Closest'
        tex.extension = 'REPEAT'
        mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def floor_texture(folder):
    """A 64x64 tile pattern (8x8 tiles of two warm tones, one-texel dark grout), saved as PNG."""
    img = bpy.data.images.new("blender-room-floor", TEX_SIZE, TEX_SIZE, alpha=False)
    px = []
    for j in range(TEX_SIZE):
        for i in range(TEX_SIZE):
            if i % 8 == 0 or j % 8 == 0:
                c = (0.25, 0.22, 0.2)                       # grout
            elif ((i // 8) + (j // 8)) % 2 == 0:
                c = (0.85, 0.7, 0.5)                        # light tile (sRGB-encoded values)
            else:
                c = (0.55, 0.35, 0.25)                      # dark tile
            px.extend((*c, 1.0))
    img.pixels[:] = px
    path = os.path.join(folder, "blender-room-floor.png")
    img.filepath_raw = path
    img.file_format = 'PNG'
    img.save()
    img.source = 'FILE'
    img.filepath = path
    img.colorspace_settings.name = 'sRGB'
    return img


def build(width, height, folder):
    white = lambert("wall_white", (0.75, 0.75, 0.72))
    blue = lambert("wall_blue", (0.25, 0.35, 0.6))
    ceiling = lambert("ceiling", (0.8, 0.8, 0.8))
    floor = lambert("floor_tiles", (1.0, 1.0, 1.0), floor_texture(folder))
    red = lambert("sphere_red", (0.7, 0.12, 0.08))
    green = lambert("monkey_green", (0.2, 0.55, 0.2))
    x0, x1, y0, y1 = -W / 2, W / 2, -D / 2, D / 2
    quad("floor", [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)], floor, (0, 0, 1),
         uv=lambda v: ((v[0] - x0) / W * TEX_REPEAT, (v[1] - y0) / D * TEX_REPEAT))
    quad("ceiling", [(x0, y0, H), (x0, y1, H), (x1, y1, H), (x1, y0, H)], ceiling, (0, 0, -1))
    quad("back_wall", [(x0, y1, 0), (x1, y1, 0), (x1, y1, H), (x0, y1, H)], white, (0, -1, 0))
    quad("front_wall", [(x0, y0, 0), (x0, y0, H), (x1, y0, H), (x1, y0, 0)], white, (0, 1, 0))
    quad("right_wall", [(x1, y0, 0), (x1, y0, H), (x1, y1, H), (x1, y1, 0)], blue, (-1, 0, 0))
    # The left wall (x = x0, facing +x) as one mesh of four quads around the window opening.
    wy0, wy1 = WINDOW_Y
    wz0, wz1 = WINDOW_Z
    ys, zs = (y0, wy0, wy1, y1), (0.0, wz0, wz1, H)
    verts = [(x0, y, z) for z in zs for y in ys]          # 4 x 4 grid, index = 4 * iz + iy
    cells = [(iy, iz) for iz in range(3) for iy in range(3) if (iy, iz) != (1, 1)]
    faces = [(4 * iz + iy, 4 * iz + iy + 1, 4 * (iz + 1) + iy + 1, 4 * (iz + 1) + iy) for iy, iz in cells]
    left = mesh_object("left_wall_window", verts, faces, white)
    for poly in left.data.polygons:
        assert poly.normal.dot(Vector((1, 0, 0))) > 0.99, ("left wall", poly.index, tuple(poly.normal))

    # Smooth-shaded objects: a subdivided UV sphere and Suzanne with a Subdivision Surface modifier.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.45, location=(0.7, 0.6, 0.45))
    sphere = bpy.context.active_object
    sphere.name = "sphere"
    bpy.ops.object.shade_smooth()
    sphere.data.materials.append(red)
    bpy.ops.mesh.primitive_monkey_add(size=0.9, location=(-0.7, 0.3, 0.55), rotation=(0.0, 0.0, math.radians(35.0)))
    monkey = bpy.context.active_object
    monkey.name = "suzanne"
    mod = monkey.modifiers.new("subsurf", 'SUBSURF')
    mod.levels = 1
    mod.render_levels = 1
    bpy.ops.object.shade_smooth()
    monkey.data.materials.append(green)

    scene, cam_obj = add_lights_and_camera(width, height, (1.2, -1.85, 1.55), (-0.3, 0.6, 0.55))
    scene.unit_settings.system = 'METRIC'
    scene.unit_settings.scale_length = 1.0


def export(path):
    bpy.ops.export_scene.gltf(
        filepath=path,
        export_format='GLB',
        export_lights=True,               # KHR_lights_punctual
        convert_lighting_mode='SPEC',     # physical units: point W -> W/(4 pi)*683 cd, sun W/m^2 -> 683 lux
        export_cameras=True,
        export_apply=True,                # the Subdivision Surface modifier
        export_yup=True,
        export_texcoords=True,
        export_normals=True,              # smooth shading -> NORMAL
        export_materials='EXPORT',
        export_image_format='AUTO',
        export_animations=False,
        export_extras=False,
    )


def main():
    path, width, height = args()
    folder = os.path.dirname(path)
    os.makedirs(folder, exist_ok=True)
    clear_scene()
    build(width, height, folder)
    export(path)
    print("wrote", path, os.path.getsize(path), "bytes")


main()
