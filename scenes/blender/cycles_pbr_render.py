"""Renders a glTF file with Blender Cycles 5 (bpy 5.0.1 as a module) as glTF specifies its
materials, a reference for bundlepath's metallic-roughness BRDF and thin-walled glass.

  /work/main/bench-out/peers-venv/bin/python scenes/blender/cycles_pbr_render.py SCENE.glb OUT_PREFIX \
      --width W --height H --spp N [--seed K] [--threads T]

Writes OUT_PREFIX.exr (linear RGBA float) and OUT_PREFIX.json (samples, Cycles' sampling time, wall).

The file is re-imported with Blender's glTF importer (physical light units: the exporter's inverse),
which maps each material to a Principled BSDF (base colour and its texture, metallic, roughness,
IOR, the normal map through a Normal Map node in tangent space). Then:
* every Principled BSDF's distribution is GGX (single scattering: bundlepath has no multiple-
  scattering energy compensation); nothing else of the node is changed (Specular IOR Level 0.5,
  Specular Tint white: glTF's F0 = ((ior - 1) / (ior + 1))^2 with Schlick-shaped metal Fresnel);
* a material with KHR_materials_transmission becomes glTF's thin-walled dielectric, not Principled's
  refracting transmission: a Mix Shader of a Transparent BSDF tinted baseColor * transmission (shadow
  rays pass it with that tint) and a sharp Glossy BSDF (white, roughness 0), mixed by Schlick's
  Fresnel F = F0 + (1 - F0)(1 - |N.I|)^5 built from a Geometry node (Cycles' Fresnel node uses the
  exact dielectric Fresnel and 1/ior from the back, which would make the pane's back a total
  internal reflector); the opaque 1 - transmission part is the Principled BSDF with transmission 0;
* sRGB colour textures are decoded to linear floats before Cycles sees them, so its bilinear filter
  runs on linear values, as glTF recommends and bundlepath does (Cycles filters 8-bit sRGB texels
  first and decodes after: 2 % on this scene's wood floor);
* lights: radius 0, soft falloff off, sun angle 0 (the importer leaves Blender's defaults);
* the camera: sensor fit vertical with the file's yfov;
* no shadow-terminator offsets; black world;
* Cycles' settings are bench/peers/cycles_peer.py's render_settings (CPU, light tree on, no adaptive
  sampling, no denoiser, no clamping, no light threshold, no glossy filter, 1024 bounces of every
  kind, 1-pixel box filter, view transform Standard).
"""
import argparse
import json
import math
import os
import struct
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "bench", "peers"))
import cycles_peer  # noqa: E402  (its main() runs only as a script)

import bpy  # noqa: E402


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--spp", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=2)
    return p.parse_args()


def gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        return json.loads(data.decode("utf-8"))
    n = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + n].decode("utf-8"))


def thin_walled_glass(mat, bsdf, transmission, ior):
    """Replace the surface by glTF's thin-walled dielectric (module docstring)."""
    tree = mat.node_tree
    nodes, links = tree.nodes, tree.links
    out = next(n for n in nodes if n.type == 'OUTPUT_MATERIAL' and n.is_active_output)
    f0 = ((ior - 1.0) / (ior + 1.0)) ** 2
    geo = nodes.new("ShaderNodeNewGeometry")
    dot = nodes.new("ShaderNodeVectorMath")
    dot.operation = 'DOT_PRODUCT'
    links.new(geo.outputs["Normal"], dot.inputs[0])
    links.new(geo.outputs["Incoming"], dot.inputs[1])
    cos = nodes.new("ShaderNodeMath")
    cos.operation = 'ABSOLUTE'
    links.new(dot.outputs["Value"], cos.inputs[0])
    one_minus = nodes.new("ShaderNodeMath")
    one_minus.operation = 'SUBTRACT'
    one_minus.use_clamp = True
    one_minus.inputs[0].default_value = 1.0
    links.new(cos.outputs["Value"], one_minus.inputs[1])
    pow5 = nodes.new("ShaderNodeMath")
    pow5.operation = 'POWER'
    links.new(one_minus.outputs["Value"], pow5.inputs[0])
    pow5.inputs[1].default_value = 5.0
    fres = nodes.new("ShaderNodeMath")
    fres.operation = 'MULTIPLY_ADD'
    links.new(pow5.outputs["Value"], fres.inputs[0])
    fres.inputs[1].default_value = 1.0 - f0
    fres.inputs[2].default_value = f0
    transparent = nodes.new("ShaderNodeBsdfTransparent")
    base = bsdf.inputs["Base Color"]
    if base.is_linked:
        print("cycles_pbr_render: %s: a base-colour texture on glass, its factor used" % mat.name)
    col = base.default_value
    transparent.inputs["Color"].default_value = (col[0], col[1], col[2], 1.0)
    try:
        mirror = nodes.new("ShaderNodeBsdfGlossy")
    except RuntimeError:
        mirror = nodes.new("ShaderNodeBsdfAnisotropic")
    mirror.distribution = 'GGX'
    mirror.inputs["Roughness"].default_value = 0.0
    mirror.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass = nodes.new("ShaderNodeMixShader")
    links.new(fres.outputs["Value"], glass.inputs["Fac"])
    links.new(transparent.outputs["BSDF"], glass.inputs[1])
    links.new(mirror.outputs["BSDF"], glass.inputs[2])
    surface = glass.outputs["Shader"]
    if transmission < 1.0:  # the opaque rest: the Principled BSDF without transmission
        bsdf.inputs["Transmission Weight"].default_value = 0.0
        rest = nodes.new("ShaderNodeMixShader")
        rest.inputs["Fac"].default_value = transmission
        links.new(bsdf.outputs["BSDF"], rest.inputs[1])
        links.new(surface, rest.inputs[2])
        surface = rest.outputs["Shader"]
    links.new(surface, out.inputs["Surface"])
    print("cycles_pbr_render: %s: thin-walled glass, transmission %g, ior %g (F0 %.4f), tint %s"
          % (mat.name, transmission, ior, f0, tuple(round(c, 4) for c in col[:3])))


def srgb_to_linear(c):
    """The sRGB transfer function's inverse (IEC 61966-2-1), per channel, on a numpy array."""
    import numpy as np
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def decode_colour_textures_before_filtering():
    """Each sRGB image an Image Texture node reads becomes a linear float image (module docstring)."""
    import numpy as np
    done = {}
    for mat in bpy.data.materials:
        if not mat.use_nodes:
            continue
        for node in mat.node_tree.nodes:
            img = getattr(node, "image", None)
            if node.type != 'TEX_IMAGE' or img is None or img.colorspace_settings.name != 'sRGB':
                continue
            if img.name not in done:
                w, h = img.size
                px = np.empty(w * h * 4, dtype=np.float32)
                img.pixels.foreach_get(px)
                px = px.reshape(-1, 4)
                px[:, :3] = srgb_to_linear(px[:, :3])
                lin = bpy.data.images.new(img.name + " linear", w, h, alpha=True, float_buffer=True)
                lin.colorspace_settings.name = 'Linear Rec.709'
                lin.pixels.foreach_set(px.ravel())
                lin.pack()
                done[img.name] = lin
                print("cycles_pbr_render: texture %s (%dx%d) decoded to linear before filtering" % (img.name, w, h))
            node.image = done[img.name]


def main():
    a = parse_args()
    t0 = time.perf_counter()
    scene_path = os.path.abspath(a.scene)
    gltf = gltf_json(scene_path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=scene_path, export_import_convert_lighting_mode='SPEC',
                              import_shading='NORMALS')
    s = bpy.context.scene
    by_name = {m.get("name"): m for m in gltf.get("materials", [])}
    for mat in bpy.data.materials:
        if not mat.use_nodes:
            continue
        bsdf = next((n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
        if bsdf is None:
            raise SystemExit("material %r has no Principled BSDF: not a glTF import?" % mat.name)
        bsdf.distribution = 'GGX'
        src = by_name.get(mat.name, {})
        ext = src.get("extensions", {})
        if "KHR_materials_transmission" in ext:
            t = ext["KHR_materials_transmission"].get("transmissionFactor", 0.0)
            ior = ext.get("KHR_materials_ior", {}).get("ior", 1.5)
            if t > 0.0:
                thin_walled_glass(mat, bsdf, t, ior)
                continue
        kinds = sorted({n.bl_idname for n in mat.node_tree.nodes})
        print("cycles_pbr_render: %s: Principled GGX, metallic %.3g, roughness %.3g, ior %.3g, nodes %s"
              % (mat.name, bsdf.inputs["Metallic"].default_value, bsdf.inputs["Roughness"].default_value,
                 bsdf.inputs["IOR"].default_value, kinds))
    decode_colour_textures_before_filtering()
    for light in bpy.data.lights:
        light.shadow_soft_size = 0.0
        if hasattr(light, "use_soft_falloff"):
            light.use_soft_falloff = False
        if light.type == 'SUN':
            light.angle = 0.0
        print("cycles_pbr_render: light %s %s energy %.6g colour %s" % (light.name, light.type, light.energy,
                                                                        tuple(light.color)))
    for obj in s.objects:
        if obj.type == 'MESH':
            # Blender 5 reads the Object's own settings (its default geometry offset, 0.1, lights a smooth
            # face whose flat normal is turned from a light); obj.cycles.shadow_terminator_* are not read.
            obj.shadow_terminator_geometry_offset = 0.0
            obj.shadow_terminator_shading_offset = 0.0
            obj.shadow_terminator_normal_offset = 0.0
    cams = [o for o in s.objects if o.type == 'CAMERA']
    if not cams:
        raise SystemExit("no camera in " + scene_path)
    s.camera = cams[0]
    yfov = next(c["perspective"]["yfov"] for c in gltf["cameras"] if c.get("type") == "perspective")
    cam = cams[0].data
    cam.sensor_fit = 'VERTICAL'
    cam.sensor_height = 24.0
    cam.lens = 12.0 / math.tan(0.5 * yfov)
    print("cycles_pbr_render: camera %s yfov %.6f (angle_y %.6f)" % (cams[0].name, yfov, cam.angle_y))
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    s.world = world
    cycles_peer.render_settings(s, a.width, a.height, a.out + ".exr", spp=a.spp, seed=a.seed, threads=a.threads)
    t1 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    t2 = time.perf_counter()
    reported = cycles_peer.cycles_render_seconds(a.out + ".exr")
    result = {"renderer": "Cycles " + bpy.app.version_string, "spp": a.spp, "seed": a.seed, "threads": a.threads,
              "render_seconds": reported if reported is not None else t2 - t1, "wall_seconds": t2 - t0}
    with open(a.out + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print("cycles_pbr_render:", json.dumps(result))


main()
