"""Renders a glTF scene with Blender Cycles 5 (PyPI bpy==5.0.1) under the conventions of
bench/peers/convert.py, for the peer harness (issue 29). Runs in the peers' venv:

  python bench/peers/cycles_peer.py SCENE OUT_PREFIX --width W --height H [--time S | --spp N]
                                    [--threads T] [--seed K] [--guiding] [--denoise]

Writes OUT_PREFIX.exr (linear RGBA float) and OUT_PREFIX.json: samples reached, the sampling time
Cycles reports (its time limit counts sampling only and overruns by up to a third), the set-up time
(scene conversion and Cycles' synchronisation: wall time of the whole render less sampling), wall.

Settings, those a Blender user renders finals with: CPU, light tree on, no adaptive sampling, no
denoiser, no clamping, no light threshold, no glossy filter, 1024 bounces of every kind (Russian
roulette stays), a 1-pixel box filter, black world, view transform Standard; with --guiding, path
guiding on surfaces (Cycles' defaults for its training); with --denoise, Blender's final-render
denoiser as it ships on by default: OpenImageDenoise on colour + albedo + normal, prefilter Accurate,
quality High (the time it takes is outside Cycles' sampling time and inside the wall time). The scene is built from convert.load():
emission Le from the front face only unless the material is double-sided (Geometry.Backfacing masks
the back; emission_sampling FRONT or FRONT_BACK), point and spot lights of 4 pi I watts with radius 0,
a sun of the file's irradiance with angle 0, the file's camera (vertical FOV, sensor fit vertical).
Materials, by convert.py's model:

* "lambert": a Diffuse BSDF (roughness 0: Lambert) of kd, times the base-colour texture (sRGB).
* "ggx" (glTF's metallic-roughness BRDF): a Principled BSDF, distribution GGX (single scattering, not
  Multiscatter GGX), as Blender's own glTF importer maps the material (io_scene_gltf2, blender/imp/
  pbrMetallicRoughness.py): Base Color = baseColorFactor times the base-colour texture, Metallic,
  Roughness (the same perceptual roughness: Cycles' alpha is its square, as glTF's), the
  metallicRoughnessTexture through Separate Color (G times roughness, B times metallic; Non-Color),
  IOR = KHR_materials_ior's, Specular IOR Level = 0.5 specularFactor, Specular Tint =
  specularColorFactor; coat, sheen, transmission, subsurface, thin film, diffuse roughness 0.
  What agrees with glTF (Cycles 5.0, svm/closure.h, closure/bsdf_microfacet.h): GGX D and Smith
  shadowing (height-correlated), alpha = roughness^2; the metal's Fresnel is Schlick's with f0 =
  baseColor (F82 tint of white is plain Schlick); metallic mixes metal and dielectric linearly.
  What differs, known:
  - the diffuse base under the dielectric specular layer is dimmed by 1 - E(wo), the layer's
    directional albedo (closure_layering_weight), glTF's fresnel_mix by 1 - max F(v.h) per pair of
    directions, which dims little at grazing views while the layer reflects much: glTF's material
    reflects more there (roughness 0.4, base 0.45, 75 degrees: 0.58 against about 0.53 with a
    1 - E(wo) base; the same at normal incidence), so Cycles renders smooth dielectrics darker (the GGX house at 64x36: -3.7 %
    image mean; with every roughness 0.3: -8.3 %; the Blender room, roughness 1, at 64x48: -0.5 %);
  - the dielectric Fresnel is the exact one of the ior remapped to [f0 specularTint, 1], glTF's
    Schlick's: equal at normal incidence and at 90 degrees, between them within 0.04 of reflectance
    (ior 1.5: 0.089 against 0.070 at 60 degrees, 0.61 against 0.65 at 85);
  - specularFactor s: glTF scales the whole Fresnel term (f0 and f90) by s, Blender's importer
    mapping scales f0 alone (through the ior); equal at s = 0 and s = 1 (every scene here), not
    between; Specular Tint also tints the metal's F82 (glTF's metal ignores specularColor);
  - ior 0 (KHR_materials_ior: f0 = 1) is drawn as ior 1e4.
* "phong" (extras.phong with ks > 0, Modified Phong): approximate: Diffuse BSDF of kd plus a Glossy
  BSDF (GGX, no Fresnel) of colour ks whose alpha is convert.phong_ggx_alpha(n) = sqrt(2 / (4n + 2)).
  GGX's half-angle lobe is not Phong's cos^n of the mirror angle: Modified Phong's lobe albedo falls
  about as cos(theta_o) (n = 20: 1.00, 0.71, 0.27 at 0, 45, 75 degrees), GGX's stays near 1 (0.97,
  0.95, 0.88), so the lobes reflect more at oblique views (the Phong house at 64x36: +6 % image mean,
  both peers alike).
"""
import argparse
import json
import math
import os
import re
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import convert  # noqa: E402

import bpy  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--time", type=float, default=0.0)
    p.add_argument("--spp", type=int, default=0)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--guiding", action="store_true")
    p.add_argument("--denoise", action="store_true")
    a = p.parse_args()
    if (a.time > 0) == (a.spp > 0):
        p.error("give exactly one of --time and --spp")
    return a


def image_node(tree, scene, ref, tmp, colour_space):
    """An Image Texture node of texture `ref` (its sampler's filter and wrap), read by the mesh's uv."""
    tex = scene["textures"][ref["texture"]]
    img = tree.nodes.new("ShaderNodeTexImage")
    img.image = bpy.data.images.load(convert.write_texture(scene, ref["texture"], tmp))
    img.image.colorspace_settings.name = colour_space
    img.interpolation = "Closest" if tex["nearest"] else "Linear"
    img.extension = {33071: "EXTEND", 33648: "MIRROR"}.get(tex["wrap_s"], "REPEAT")
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = "uv"
    tree.links.new(uv.outputs["UV"], img.inputs["Vector"])
    return img


def colour_input(tree, socket, colour, ref, scene, tmp):
    """socket = colour, times the (sRGB) texture `ref` where there is one."""
    if ref is None:
        socket.default_value = (*colour, 1.0)
        return
    img = image_node(tree, scene, ref, tmp, "sRGB")
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    mix.blend_type = "MULTIPLY"
    mix.inputs["Factor"].default_value = 1.0
    tree.links.new(img.outputs["Color"], mix.inputs[6])
    mix.inputs[7].default_value = (*colour, 1.0)
    tree.links.new(mix.outputs[2], socket)


def scaled_channel(tree, separate, channel, factor, socket):
    """socket = factor * channel of a Separate Color node."""
    mul = tree.nodes.new("ShaderNodeMath")
    mul.operation = "MULTIPLY"
    tree.links.new(separate.outputs[channel], mul.inputs[0])
    mul.inputs[1].default_value = factor
    tree.links.new(mul.outputs["Value"], socket)


def principled(tree, m, scene, tmp):
    """glTF's metallic-roughness material as Blender's glTF importer maps it (module docstring)."""
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.distribution = "GGX"  # single scattering, as glTF (not MULTI_GGX's energy compensation)
    colour_input(tree, bsdf.inputs["Base Color"], m["base_color"], m["texture"], scene, tmp)
    bsdf.inputs["Metallic"].default_value = m["metallic"]
    bsdf.inputs["Roughness"].default_value = m["roughness"]  # Cycles squares it, as glTF does
    if m["mr_texture"] is not None:  # G: roughness, B: metallic, linear
        img = image_node(tree, scene, m["mr_texture"], tmp, "Non-Color")
        sep = tree.nodes.new("ShaderNodeSeparateColor")
        sep.mode = "RGB"
        tree.links.new(img.outputs["Color"], sep.inputs["Color"])
        scaled_channel(tree, sep, "Green", m["roughness"], bsdf.inputs["Roughness"])
        scaled_channel(tree, sep, "Blue", m["metallic"], bsdf.inputs["Metallic"])
    # KHR_materials_ior (0 means f0 = 1: a very large ior) and KHR_materials_specular as Blender's
    # importer maps them: Specular IOR Level = 0.5 specular, Specular Tint = specularColor
    bsdf.inputs["IOR"].default_value = m["ior"] if m["ior"] >= 1.0 else 1e4
    bsdf.inputs["Specular IOR Level"].default_value = 0.5 * m["specular_weight"]
    bsdf.inputs["Specular Tint"].default_value = (*m["specular_color"], 1.0)
    for name in ("Coat Weight", "Sheen Weight", "Transmission Weight", "Subsurface Weight", "Emission Strength",
                 "Diffuse Roughness", "Thin Film Thickness"):
        if name in bsdf.inputs:
            bsdf.inputs[name].default_value = 0.0
    return bsdf.outputs["BSDF"]


def glossy_node(tree):
    try:
        return tree.nodes.new("ShaderNodeBsdfGlossy")
    except RuntimeError:  # Blender 4+: the Glossy BSDF is the former Anisotropic node
        return tree.nodes.new("ShaderNodeBsdfAnisotropic")


def make_material(m, index, scene, tmp):
    mat = bpy.data.materials.new("m%d_%s" % (index, m["name"]))
    mat.use_nodes = True
    tree = mat.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    if m["model"] == "ggx":
        surface = principled(tree, m, scene, tmp)
    else:
        diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0
        colour_input(tree, diffuse.inputs["Color"], m["texture"]["factor"] if m["texture"] else m["kd"],
                     m["texture"], scene, tmp)
        surface = diffuse.outputs["BSDF"]
        if m["model"] == "phong":  # kd Lambert + ks times a GGX lobe without Fresnel (approximate)
            glossy = glossy_node(tree)
            glossy.distribution = "GGX"
            glossy.inputs["Color"].default_value = (*m["ks"], 1.0)
            glossy.inputs["Roughness"].default_value = math.sqrt(convert.phong_ggx_alpha(m["shininess"]))
            add = tree.nodes.new("ShaderNodeAddShader")
            tree.links.new(surface, add.inputs[0])
            tree.links.new(glossy.outputs["BSDF"], add.inputs[1])
            surface = add.outputs["Shader"]
    le = m["emission"]
    if max(le) > 0.0:
        peak = max(le)
        emit = tree.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (le[0] / peak, le[1] / peak, le[2] / peak, 1.0)
        emit.inputs["Strength"].default_value = peak
        if not m["double_sided"]:  # glTF: single-sided emitters are black from behind
            geo = tree.nodes.new("ShaderNodeNewGeometry")
            front = tree.nodes.new("ShaderNodeMath")
            front.operation = "MULTIPLY_ADD"  # peak * (-backfacing) + peak
            front.inputs[1].default_value = -peak
            front.inputs[2].default_value = peak
            tree.links.new(geo.outputs["Backfacing"], front.inputs[0])
            tree.links.new(front.outputs["Value"], emit.inputs["Strength"])
        add = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(surface, add.inputs[0])
        tree.links.new(emit.outputs["Emission"], add.inputs[1])
        surface = add.outputs["Shader"]
        # light-tree sampling of the emitting sides only (Cycles' default AUTO would guess them)
        mat.cycles.emission_sampling = "FRONT_BACK" if m["double_sided"] else "FRONT"
    tree.links.new(surface, out.inputs["Surface"])
    return mat


def make_mesh(mesh, mat, m):
    me = bpy.data.meshes.new(mesh["name"])
    me.from_pydata([tuple(p) for p in mesh["positions"]], [], [tuple(t) for t in mesh["triangles"]])
    if mesh["uvs"] is not None:
        layer = me.uv_layers.new(name="uv")
        flat = []
        for tri in mesh["triangles"]:
            for i in tri:
                u, v = mesh["uvs"][i]
                flat += [u, 1.0 - v]  # glTF's v runs down the image, Blender's up
        layer.data.foreach_set("uv", flat)
    me.materials.append(mat)
    me.validate(clean_customdata=False)
    if mesh["normals"] is not None:
        me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
        me.normals_split_custom_set_from_vertices([tuple(n) for n in mesh["normals"]])
    me.update()
    obj = bpy.data.objects.new(mesh["name"], me)
    # Blender 5 reads the Object's own settings (its default geometry offset, 0.1, lights a smooth
    # face whose flat normal is turned from a light); obj.cycles.shadow_terminator_* are not read.
    obj.shadow_terminator_geometry_offset = 0.0
    obj.shadow_terminator_shading_offset = 0.0
    obj.shadow_terminator_normal_offset = 0.0
    return obj


def look_rotation(forward, up=None):
    """A rotation whose -Z is `forward` (and +Y `up`, when given)."""
    f = Vector(forward).normalized()
    if up is None:
        return f.to_track_quat("-Z", "Y").to_matrix().to_4x4()
    u = Vector(up).normalized()
    r = f.cross(u).normalized()
    u = r.cross(f)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2] = r[i], u[i], -f[i]
    return m


def build(scene, coll, tmp):
    mats = {}
    for mesh in scene["meshes"]:
        k = mesh["material"]
        if k not in mats:
            mats[k] = make_material(scene["materials"][k], k, scene, tmp)
        coll.objects.link(make_mesh(mesh, mats[k], scene["materials"][k]))
    for i, light in enumerate(scene["lights"]):
        kind = {"point": "POINT", "spot": "SPOT", "directional": "SUN"}[light["kind"]]
        data = bpy.data.lights.new("light%d" % i, kind)
        value = [4.0 * math.pi * v for v in light["intensity"]] if kind != "SUN" else light["intensity"]
        peak = max(value)
        data.color = [v / peak for v in value] if peak > 0 else (1.0, 1.0, 1.0)
        data.energy = peak
        if kind == "SUN":
            data.angle = 0.0
        else:
            data.shadow_soft_size = 0.0
            if hasattr(data, "use_soft_falloff"):
                data.use_soft_falloff = False
        if kind == "SPOT":
            # Blender's blend is a smoothstep over the cone's edge, glTF's a quadratic: close, not equal.
            data.spot_size = 2.0 * light["outer_cone"]
            data.spot_blend = (light["outer_cone"] - light["inner_cone"]) / light["outer_cone"]
        obj = bpy.data.objects.new("light%d" % i, data)
        obj.matrix_world = Matrix.Translation(light["position"]) @ look_rotation(light["direction"])
        coll.objects.link(obj)
    c = scene["camera"]
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.sensor_height = 24.0
    cam.lens = 12.0 / math.tan(0.5 * c["yfov"])
    cam.clip_start = 1e-4
    cam.clip_end = 1e6
    obj = bpy.data.objects.new("camera", cam)
    obj.matrix_world = Matrix.Translation(c["position"]) @ look_rotation(c["forward"], c["up"])
    coll.objects.link(obj)
    return obj


def render_settings(s, width, height, exr_path, spp=0, time_limit=0.0, seed=1, threads=1, guiding=False,
                    denoise=False):
    """The Cycles settings of the harness (the module docstring), on scene `s`; the output is a 32-bit
    float RGBA EXR at exr_path. bench/pbr_room.sh's Cycles render reuses them."""
    s.render.engine = "CYCLES"
    cy = s.cycles
    cy.device = "CPU"
    cy.samples = spp if spp > 0 else 1 << 24
    cy.time_limit = time_limit
    cy.use_adaptive_sampling = False
    cy.seed = seed
    cy.use_animated_seed = False
    cy.use_denoising = denoise
    if denoise:
        cy.denoiser = "OPENIMAGEDENOISE"
        cy.denoising_input_passes = "RGB_ALBEDO_NORMAL"
        cy.denoising_prefilter = "ACCURATE"
        cy.denoising_quality = "HIGH"
    for k in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
              "transparent_max_bounces"):
        setattr(cy, k, 1024)
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.use_light_tree = True
    cy.use_guiding = guiding
    if guiding:
        cy.use_surface_guiding = True
        cy.use_volume_guiding = False
    s.render.film_transparent = False
    s.view_settings.view_transform = "Standard"
    s.view_settings.look = "None"
    s.render.resolution_x = width
    s.render.resolution_y = height
    s.render.resolution_percentage = 100
    s.render.use_compositing = False
    s.render.use_sequencer = False
    s.render.threads_mode = "FIXED"
    s.render.threads = threads
    st = s.render.image_settings
    st.file_format = "OPEN_EXR"
    st.color_depth = "32"
    st.color_mode = "RGBA"
    st.exr_codec = "ZIP"
    s.render.filepath = os.path.abspath(exr_path)
    s.render.use_file_extension = False


def cycles_render_seconds(exr_path):
    """Cycles' sampling time from the EXR header (None when not found)."""
    import subprocess
    reported = None
    probe = ("import OpenEXR, json, sys\nwith OpenEXR.File(sys.argv[1]) as f:\n"
             "    print(json.dumps({k: str(v) for k, v in f.header().items() if k.startswith('cycles.')}))")
    try:
        header = json.loads(subprocess.run([sys.executable, "-c", probe, exr_path], check=True,
                                           capture_output=True, text=True).stdout)
        for key, v in header.items():
            m = re.match(r"(?:(\d+):)?(\d+):(\d+(?:\.\d+)?)$", v)
            if key.endswith(".render_time") and m:
                reported = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))
    except (subprocess.CalledProcessError, ValueError) as e:
        print("cycles_peer: EXR header not read:", e, file=sys.stderr)
    return reported


def main():
    a = parse_args()
    t0 = time.perf_counter()
    scene = convert.load(a.scene)
    for w in scene["warnings"]:
        print("cycles_peer: warning:", w, file=sys.stderr)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = bpy.context.scene
    tmp = tempfile.mkdtemp(prefix="cycles-peer-")
    s.camera = build(scene, s.collection, tmp)
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    s.world = world
    render_settings(s, a.width, a.height, a.out + ".exr", a.spp, a.time, a.seed, a.threads, a.guiding, a.denoise)
    stats = []
    bpy.app.handlers.render_stats.append(lambda text, *_: stats.append(text))
    t1 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    t2 = time.perf_counter()
    # The progress lines name the samples done ("Sample 33/16777216"; the last one says 0).
    done = [int(m.group(1)) for m in (re.search(r"Sample (\d+)/\d+", t) for t in stats) if m]
    samples = max(done) if done else None
    # Cycles' own times are in the EXR header (cycles.<layer>.render_time: sampling). Read in a
    # process without bpy: with bpy loaded, the OpenEXR module sees none of the custom attributes.
    reported = cycles_render_seconds(a.out + ".exr")
    render = reported if reported is not None else t2 - t1
    result = {"renderer": "Cycles " + bpy.app.version_string, "guiding": a.guiding, "spp": samples,
              "render_seconds": render, "render_seconds_source": "cycles" if reported is not None else "wall",
              "setup_seconds": (t1 - t0) + max(0.0, (t2 - t1) - render), "wall_seconds": t2 - t0,
              "threads": a.threads, "seed": a.seed, "last_stats": stats[-1] if stats else ""}
    with open(a.out + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print("cycles_peer:", json.dumps(result))


if __name__ == "__main__":
    main()
