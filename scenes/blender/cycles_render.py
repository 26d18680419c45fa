# Renders a glTF file with Blender Cycles as an unbiased Lambert reference for bundlepath.
#
#   blender -b --factory-startup --python scenes/blender/cycles_render.py -- \
#       SCENE.glb OUT.exr WIDTH HEIGHT SPP [SEED] [THREADS]
#
# The file is re-imported with Blender's own glTF importer (physical light units, the exporter's
# inverse: cd * 4 pi / 683 W for point lights, lux / 683 W/m^2 for suns) into an empty scene, and:
# * every material becomes pure Lambert: a Diffuse BSDF (roughness 0) fed by what fed the
#   Principled BSDF's Base Color (the texture node and its sRGB image, or the colour), as our loader
#   reads Specular 0 / Metallic 0 (docs/design.md section 6); emission, if any, is kept;
# * glTF's punctual lights are points and a parallel sun: radius 0, sun angle 0 (the importer leaves
#   Blender's defaults, 0.25 m and 0.53 degrees, which are not in the file);
# * Cycles on the CPU, fixed seed, no adaptive sampling, no denoising, no clamping, no light
#   threshold, no glossy filter, 1024 bounces of every kind (Russian roulette stays: unbiased),
#   no path guiding, a 1-pixel box filter (ours: uniform samples over the pixel), no shadow-terminator offsets,
#   black world (the file has none; ours renders --environment 0,0,0), opaque film, view transform
#   Standard (the EXR is linear scene radiance either way);
# * output: a 32-bit float RGBA OpenEXR.
import math
import os
import sys

import bpy


def args():
    argv = sys.argv
    rest = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(rest) < 5:
        raise SystemExit("usage: blender -b --factory-startup --python scenes/blender/cycles_render.py -- "
                         "SCENE.glb OUT.exr WIDTH HEIGHT SPP [SEED] [THREADS]")
    seed = int(rest[5]) if len(rest) > 5 else 1
    threads = int(rest[6]) if len(rest) > 6 else 0
    return os.path.abspath(rest[0]), os.path.abspath(rest[1]), int(rest[2]), int(rest[3]), int(rest[4]), seed, threads


def make_lambert(mat):
    """Replace the material's surface by a Diffuse BSDF with the Principled BSDF's base colour."""
    if not mat.use_nodes:
        mat.use_nodes = True
    tree = mat.node_tree
    out = next((n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL'), None)
    bsdf = next((n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
    if out is None or bsdf is None:
        raise SystemExit("material %r has no Principled BSDF / output: not a glTF import?" % mat.name)
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    base = bsdf.inputs["Base Color"]
    diffuse.inputs["Color"].default_value = base.default_value
    if base.is_linked:
        tree.links.new(base.links[0].from_socket, diffuse.inputs["Color"])
    surface = diffuse.outputs["BSDF"]
    emission = bsdf.inputs["Emission"]
    strength = bsdf.inputs["Emission Strength"].default_value
    if emission.is_linked or (max(emission.default_value[:3]) > 0.0 and strength > 0.0):
        emit = tree.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = emission.default_value
        if emission.is_linked:
            tree.links.new(emission.links[0].from_socket, emit.inputs["Color"])
        emit.inputs["Strength"].default_value = strength
        add = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(diffuse.outputs["BSDF"], add.inputs[0])
        tree.links.new(emit.outputs["Emission"], add.inputs[1])
        surface = add.outputs["Shader"]
    tree.links.new(surface, out.inputs["Surface"])
    for node in tree.nodes:
        if node.type == 'TEX_IMAGE' and node.image is not None:
            print("cycles_render: %s: texture %s (%s, %s, %s)" % (mat.name, node.image.name,
                  node.image.colorspace_settings.name, node.interpolation, node.extension))


def main():
    scene_path, out_path, width, height, spp, seed, threads = args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Debian 12's Blender 3.4 importer uses np.bool, which Debian 12's NumPy 1.24 no longer has
    # ("module 'numpy' has no attribute 'bool'" while reading smooth-shaded meshes): restore the alias.
    import numpy
    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    bpy.ops.import_scene.gltf(filepath=scene_path, convert_lighting_mode='SPEC', import_shading='NORMALS')
    scene = bpy.context.scene

    for mat in bpy.data.materials:
        make_lambert(mat)
    for light in bpy.data.lights:
        light.shadow_soft_size = 0.0
        if light.type == 'SUN':
            light.angle = 0.0
        print("cycles_render: light %s %s energy %.6g colour %s" % (light.name, light.type, light.energy,
                                                                   tuple(light.color)))
    for obj in scene.objects:
        if obj.type == 'MESH':
            # Blender 5 reads the Object's own settings (its default geometry offset, 0.1, lights a smooth
            # face whose flat normal is turned from a light); obj.cycles.shadow_terminator_* are not read.
            obj.shadow_terminator_geometry_offset = 0.0
            obj.shadow_terminator_shading_offset = 0.0
            obj.shadow_terminator_normal_offset = 0.0
    cams = [o for o in scene.objects if o.type == 'CAMERA']
    if not cams:
        raise SystemExit("no camera in " + scene_path)
    scene.camera = cams[0]
    cam = cams[0].data
    print("cycles_render: camera %s sensor_fit %s yfov %.6f" % (cams[0].name, cam.sensor_fit, cam.angle_y))

    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    scene.render.engine = 'CYCLES'
    cy = scene.cycles
    cy.device = 'CPU'
    cy.samples = spp
    cy.use_adaptive_sampling = False
    cy.seed = seed
    cy.use_animated_seed = False
    cy.use_denoising = False
    cy.max_bounces = 1024
    cy.diffuse_bounces = 1024
    cy.glossy_bounces = 1024
    cy.transmission_bounces = 1024
    cy.volume_bounces = 1024
    cy.transparent_max_bounces = 1024
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.pixel_filter_type = 'BOX'
    cy.filter_width = 1.0
    if hasattr(cy, "use_guiding"):  # path guiding (3.4+, off by default): keep it off
        cy.use_guiding = False
    if hasattr(cy, "use_light_tree"):  # Blender 3.5+; 3.4 has none
        cy.use_light_tree = False
    scene.render.film_transparent = False
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = 1.0
    scene.render.pixel_aspect_y = 1.0
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    if threads > 0:
        scene.render.threads_mode = 'FIXED'
        scene.render.threads = threads
    scene.render.image_settings.file_format = 'OPEN_EXR'
    scene.render.image_settings.color_depth = '32'
    scene.render.image_settings.color_mode = 'RGBA'
    scene.render.image_settings.exr_codec = 'ZIP'
    scene.render.filepath = out_path
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)
    print("cycles_render: wrote", out_path)


main()
