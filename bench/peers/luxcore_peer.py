"""Renders a glTF scene with LuxCoreRender 2.11 (PyPI pyluxcore) under the conventions of
bench/peers/convert.py, for the peer harness (issue 29). Runs in the peers' venv:

  python bench/peers/luxcore_peer.py SCENE OUT_PREFIX --width W --height H [--time S | --spp N]
                                     [--threads T] [--seed K] [--photongi] [--light-strategy S]
                                     [--mesh-dls enabled|disabled|auto] [--mesh-lights dls-only|mis]
                                     [--engine pathcpu|pathocl]

Writes OUT_PREFIX.exr (linear RGB float), OUT_PREFIX.luxcore.log (LuxCore's log, as it speaks: a
run that hangs or dies keeps it) and OUT_PREFIX.json: passes (samples per pixel) reached, the
rendering time (from the first pass to the stop, the budget of --time), the set-up time (scene
parse, BVH, the DLS and PhotonGI caches: the wall time before the first pass, less the kernels'
compilation), PATHOCL's kernel compilation time (from LuxCore's log; 0 for PATHCPU), wall time.

--engine pathocl: LuxCore's OpenCL path tracer on every OpenCL device it finds (no native CPU
threads beside them), otherwise as PATHCPU below. On PoCL's CPU device (2-core AMD EPYC, PoCL 3.1)
its kernels' compilation had not finished after 15 minutes of a core: use it where a GPU driver
is installed.

PATHCPU, Sobol sampler, 1024 bounces of every kind (Russian roulette from depth 3, LuxCore's
default), no clamping, a 1-pixel box filter (LuxCore's filter width is a radius: 0.5), the light
strategy DLS_CACHE (LuxCore's choice for many lights); mesh emitters with direct light sampling
ENABLED (--mesh-dls) and, after the first bounce, reached by light sampling only (--mesh-lights
dls-only: invisible to indirect rays, so the light samples carry them alone, unweighted; reported
to be needed because LuxCore 2.11's MIS over-counts mesh lights under Russian roulette; on the
Cornell box both agree with the reference's mean, -0.09 % and -0.06 % at 160x90, 15 s, and on the
Lambert house, -0.04 % and +0.07 % at 128x72, 30 s); with --photongi the PhotonGI indirect cache
(LuxCore's defaults otherwise).
The scene: materials by convert.py's model (below), emission Le with gain 1 and no normalisation
(LuxCore emits from the front face only: a double-sided emitter gets a second, flipped copy 1e-5 of
the scene's size behind it), point lights of gain 4 pi I
(LuxCore's point light radiates gain / 4 pi W/sr), spot lights likewise with LuxCore's own cone
falloff (close to glTF's, not equal), the sun as a `sharpdistant` light of the file's irradiance,
the camera from the file (LuxCore's fieldofview spans the longer image side).

Materials (LuxCore 2.11, src/slg/materials/ and materialdefs_funcs_generic.cl):
* "lambert": matte of kd (times the base-colour texture: imagemap, gamma 2.2).
* "ggx" (glTF's metallic-roughness BRDF): glossy2, not disney. glossy2 is kd/pi (1 - S(v.h)) under
  a coat D G S / (4 |n.wo| |n.wi|) with S Schlick's Fresnel of f0 = ks (index 0: ks as given) and D
  Schlick's distribution r / (pi (cos^2 r + 1 - cos^2)^2), which is GGX's D with r = alpha^2
  (uroughness = vroughness = alpha = roughness^2); so it is glTF's fresnel_mix term for term except
  the shadowing. The dielectric is glossy2(kd = baseColor, ks = dielectric f0), the metal
  glossy2(kd = 0, ks = baseColor) (conductor_fresnel: Schlick's of f0 = baseColor), mixed by
  metallic (a `mix` material, amount = metallic); KHR_materials_specular's specular s < 1 as
  mix(matte(baseColor), glossy2, s), which is fresnel_mix of weight s exactly; the
  metallicRoughnessTexture as an imagemap (gamma 1) split into G (roughness, squared for alpha) and B
  (metallic) times the factors; multibounce off. glossy2 coats the front face only (its back is
  kd alone; with `doublesided` on, the coat's samples on the back are all dropped: its pdf D / (4
  wo.h) is negative there in SchlickBSDF_CoatingSampleF; the GGX house came out -24 % so), so a
  double-sided glTF material gets a flipped copy of its mesh just behind, as a double-sided emitter.
  LuxCore's disney was not chosen: its diffuse is Burley's (retro-reflective, 0.5 + 2 roughness
  cos^2 at grazing) and not dimmed by the Fresnel term, its dielectric f0 is 0.08 specular (at most
  0.08), and its shadowing is separable.
  What differs from glTF, known:
  - shadowing: glossy2's G is Schlick's separable G1 = cos / (cos (1 - k) + k) with k = alpha^2,
    glTF's height-correlated Smith GGX: close for smooth surfaces (alpha 0.16: within 3 % at
    cos 0.2; alpha 0.36: 4 % at cos 0.5), more shadowing for rough ones (alpha 1: G1 = cos against
    2 cos / (1 + cos), 25 % less at cos 0.5): a rough dielectric reflects up to 3 % less (alpha 1,
    f0 0.04, at 75 degrees);
  - sampling, a LuxCore 2.11 bias: SchlickDistribution_SampleH draws h with density D(h) cos(theta_h)
    (GGX's usual inversion) but reports D(h), so every glossy2 sample of a path's next direction is
    divided by a density too large (the mixture's too, the base's samples included): paths go on
    from rough glossy2 surfaces with too little weight (from its formulas, base 0.75, alpha 1: -4 %
    at normal view, -10 % at 60 degrees; alpha 0.09: -1 %); direct light (Evaluate) is unaffected.
    Compounded over the bounces of a closed room it dominates: the GGX house at 64x36 (walls and
    ceiling at roughness 1) -10 % image mean, with every roughness 0.3 -1.8 %; the Blender room
    (roughness 1, f0 0) -8.6 %, where matte materials give +0.7 %;
  - the base is dimmed per channel by 1 - S, glTF's by 1 - max(F): equal for a grey f0 (every
    material without a coloured specularColor);
  - ior 0 (f0 = 1) works (ks 1); the specular textures are not read (nor by bundlepath).
* "phong" (extras.phong with ks > 0, Modified Phong): approximate, as Cycles': mix(matte(kd / (1 -
  max ks)), glossy2(kd 0, ks = ks / max ks: Fresnel 1 for a grey ks), amount max ks) = kd Lambert + ks
  GGX lobe of alpha convert.phong_ggx_alpha(n) = sqrt(2 / (4n + 2)); GGX's half-angle lobe is not
  Phong's cos^n of the mirror angle (its albedo stays near 1 where Modified Phong's falls about as
  cos(theta_o): the Phong house at 64x36, +6 % image mean, as Cycles'), and a coloured ks gets
  Schlick's rise to white at grazing.

LuxCore's CPU engines never need OpenCL, and pyluxcore's bundled allocator crashes when LuxCore opens
PoCL: for them OCL_ICD_VENDORS is pointed at an empty folder before pyluxcore loads; PATHOCL runs
with the allocator preloaded (_opencl_engine_environment).
"""
import argparse
import json
import math
import os
import re
import struct
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import convert  # noqa: E402


def _opencl_engine_environment():
    """PATHOCL opens the OpenCL vendors, where pyluxcore's bundled TBB allocator, loaded as a
    dependency, frees what the ICD loader and PoCL allocated ("double free or corruption"): with the
    allocator preloaded, every allocation is its own. So a PATHOCL run re-executes itself once with
    LD_PRELOAD naming it (and PoCL's threads limited to --threads); the CPU engines hide the vendors."""
    argv = sys.argv[1:]
    if "--engine" not in argv or argv[argv.index("--engine") + 1:][:1] != ["pathocl"]:
        os.environ["OCL_ICD_VENDORS"] = tempfile.mkdtemp(prefix="no-ocl-vendors-")
        return
    if "tbbmalloc_proxy" in os.environ.get("LD_PRELOAD", ""):
        return
    import glob
    import importlib.util
    libs = os.path.join(os.path.dirname(os.path.dirname(importlib.util.find_spec("pyluxcore").origin)),
                        "pyluxcore.libs")
    proxy = sorted(glob.glob(os.path.join(libs, "libtbbmalloc_proxy*.so*")))
    if not proxy:
        sys.exit("luxcore_peer: no libtbbmalloc_proxy in %s: PATHOCL would crash opening OpenCL" % libs)
    env = dict(os.environ, LD_PRELOAD=":".join(filter(None, [proxy[0], os.environ.get("LD_PRELOAD")])))
    if "--threads" in argv:
        env.setdefault("POCL_MAX_PTHREAD_COUNT", argv[argv.index("--threads") + 1])
    os.execve(sys.executable, [sys.executable] + sys.argv, env)


_opencl_engine_environment()
import numpy as np  # noqa: E402
import OpenEXR  # noqa: E402  (before pyluxcore: its malloc proxy breaks a later import)
import pyluxcore  # noqa: E402


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
    p.add_argument("--photongi", action="store_true")
    p.add_argument("--engine", default="pathcpu", choices=["pathcpu", "pathocl"])
    p.add_argument("--light-strategy", default="DLS_CACHE")
    p.add_argument("--mesh-dls", default="enabled", choices=["enabled", "disabled", "auto"])
    p.add_argument("--mesh-lights", default="dls-only", choices=["dls-only", "mis"])
    a = p.parse_args()
    if (a.time > 0) == (a.spp > 0):
        p.error("give exactly one of --time and --spp")
    return a


def write_ply(path, positions, triangles, normals=None, uvs=None):
    pos = np.asarray(positions, dtype=np.float32).reshape(-1, 3)
    cols = [pos]
    props = ["x", "y", "z"]
    if normals is not None:
        cols.append(np.asarray(normals, dtype=np.float32).reshape(-1, 3))
        props += ["nx", "ny", "nz"]
    if uvs is not None:
        # glTF's uv as they are: LuxCore's imagemap reads v down the image like glTF (flipping v
        # here gave the Blender room's tiled floor relMSE 0.73 against the reference, 0.013 without)
        cols.append(np.asarray(uvs, dtype=np.float32).reshape(-1, 2))
        props += ["s", "t"]
    verts = np.hstack(cols).astype("<f4")
    tris = np.asarray(triangles, dtype="<i4").reshape(-1, 3)
    faces = np.zeros(len(tris), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = tris
    with open(path, "wb") as f:
        head = ["ply", "format binary_little_endian 1.0", "element vertex %d" % len(verts)]
        head += ["property float %s" % p for p in props]
        head += ["element face %d" % len(tris), "property list uchar int vertex_indices", "end_header"]
        f.write(("\n".join(head) + "\n").encode("ascii"))
        f.write(verts.tobytes())
        f.write(faces.tobytes())


def vec(v):
    return " ".join("%.9g" % x for x in v)


def screen_window(width, height):
    """LuxCore's own screen window (projective.cpp: the longer side spans [-1, 1]), moved by one
    pixel along -y: with the automatic window, LuxCore's film (first row at the bottom) comes out one
    row lower than the view that glTF, bundlepath and Cycles share (measured on the Cornell box at
    128x128: relMSE 0.94 against the reference before, 0.0018 after, the light's edge rows moved
    by one; the window moved the other way gives 8.3)."""
    frame = width / height
    x, y = (frame, 1.0) if frame < 1.0 else (1.0, 1.0 / frame)
    pixel = 2.0 / max(width, height)
    return [-x, x, -y - pixel, y - pixel]


def image_texture(scene, ref, tex_name, gamma, tmp):
    """An imagemap texture `tex_name` of texture `ref` (sRGB as gamma 2.2, or linear: gamma 1)."""
    tex = scene["textures"][ref["texture"]]
    path = convert.write_texture(scene, ref["texture"], tmp)
    wrap = {33071: "clamp", 33648: "repeat"}.get(tex["wrap_s"], "repeat")  # LuxCore has no mirror
    t = "scene.textures." + tex_name
    return [t + ".type = imagemap", '%s.file = "%s"' % (t, path), "%s.gamma = %g" % (t, gamma),
            "%s.wrap = %s" % (t, wrap), "%s.filter = %s" % (t, "nearest" if tex["nearest"] else "linear")]


def scale_texture(tex_name, texture1, texture2):
    t = "scene.textures." + tex_name
    return [t + ".type = scale", t + ".texture1 = " + texture1, t + ".texture2 = " + texture2]


def glossy2(name, kd, ks, uroughness):
    """LuxCore's glossy2 (module docstring): kd Lambert under a GGX coat of Schlick Fresnel f0 = ks."""
    p = "scene.materials." + name
    return [p + ".type = glossy2", p + ".kd = " + kd, p + ".ks = " + ks, p + ".index = 0",
            p + ".uroughness = " + uroughness, p + ".vroughness = " + uroughness, p + ".multibounce = 0",
            p + ".doublesided = 0"]


def mix(name, material1, material2, amount):
    """LuxCore's mix: (1 - amount) material1 + amount material2."""
    p = "scene.materials." + name
    return [p + ".type = mix", p + ".material1 = " + material1, p + ".material2 = " + material2,
            p + ".amount = " + amount]


def material_props(scene, m, k, name, tmp):
    """Material `name` for convert.py's material m (index k), by its model (module docstring); the
    parts of a mix are defined before it (LuxCore has no forward references)."""
    lines = []
    t = m["texture"]
    colour = vec(m["kd"] if m["model"] != "ggx" else m["base_color"])
    if t is not None:  # the texel times the factor (kd, or baseColorFactor)
        lines += image_texture(scene, t, "t%d" % k, 2.2, tmp) + scale_texture("tk%d" % k, "t%d" % k, vec(t["factor"]))
        colour = "tk%d" % k
    if m["model"] == "lambert":
        return lines + ["scene.materials.%s.type = matte" % name, "scene.materials.%s.kd = %s" % (name, colour)]
    if m["model"] == "phong":
        # kd Lambert + ks GGX lobe (F = 1: glossy2 with ks 1, kd 0), mixed with amount max(ks)
        w = max(m["ks"])
        lines += ["scene.materials.%s_kd.type = matte" % name,
                  "scene.materials.%s_kd.kd = %s" % (name, vec([min(v / (1.0 - w), 1.0) if w < 1.0 else 0.0
                                                                for v in m["kd"]]))]
        lines += glossy2(name + "_ks", "0 0 0", vec([v / w for v in m["ks"]]),
                         "%.9g" % convert.phong_ggx_alpha(m["shininess"]))
        return lines + mix(name, name + "_kd", name + "_ks", "%.9g" % w)
    # glTF's metallic-roughness: uroughness = alpha = roughness^2, metallic, from the texture if any
    alpha, metallic = "%.9g" % (m["roughness"] ** 2), "%.9g" % m["metallic"]
    textured_metallic = False
    if m["mr_texture"] is not None:
        lines += image_texture(scene, m["mr_texture"], "tm%d" % k, 1.0, tmp)
        for channel, part in ((1, "g"), (2, "b")):
            lines += ["scene.textures.tm%s%d.type = splitfloat3" % (part, k),
                      "scene.textures.tm%s%d.texture = tm%d" % (part, k, k),
                      "scene.textures.tm%s%d.channel = %d" % (part, k, channel)]
        lines += scale_texture("tr%d" % k, "tmg%d" % k, "%.9g" % m["roughness"])
        lines += scale_texture("ta%d" % k, "tr%d" % k, "tr%d" % k)
        lines += scale_texture("tmm%d" % k, "tmb%d" % k, "%.9g" % m["metallic"])
        alpha, metallic = "ta%d" % k, "tmm%d" % k
        textured_metallic = m["metallic"] > 0.0
    dielectric = m["metallic"] < 1.0 or textured_metallic
    metal = m["metallic"] > 0.0
    # the parts of a mix get suffixes; a material of one part is that part under its own name
    d_name, m_name = (name + "_d", name + "_m") if dielectric and metal else (name, name)
    if dielectric:
        sf = m["specular_weight"]
        if sf <= 0.0:  # no Fresnel layer: Lambert
            lines += ["scene.materials.%s.type = matte" % d_name, "scene.materials.%s.kd = %s" % (d_name, colour)]
        elif sf >= 1.0:
            lines += glossy2(d_name, colour, vec(m["dielectric_f0"]), alpha)
        else:  # fresnel_mix of weight s is exactly (1 - s) Lambert + s (the same of weight 1)
            lines += ["scene.materials.%s_l.type = matte" % d_name, "scene.materials.%s_l.kd = %s" % (d_name, colour)]
            lines += glossy2(d_name + "_g", colour, vec(m["dielectric_f0"]), alpha)
            lines += mix(d_name, d_name + "_l", d_name + "_g", "%.9g" % sf)
    if metal:  # conductor_fresnel: Schlick's of f0 = baseColor, no diffuse
        lines += glossy2(m_name, "0 0 0", colour, alpha)
    if dielectric and metal:
        lines += mix(name, d_name, m_name, metallic)
    return lines


def scene_props(scene, a, tmp):
    lines = []
    c = scene["camera"]
    aspect = a.width / a.height
    fov = 2.0 * math.degrees(math.atan(math.tan(0.5 * c["yfov"]) * max(aspect, 1.0)))
    target = [p + f for p, f in zip(c["position"], c["forward"])]
    lines += ["scene.camera.type = perspective", "scene.camera.lookat.orig = " + vec(c["position"]),
              "scene.camera.lookat.target = " + vec(target), "scene.camera.up = " + vec(c["up"]),
              "scene.camera.fieldofview = %.9g" % fov, "scene.camera.cliphither = 1e-4",
              "scene.camera.screenwindow = %s" % vec(screen_window(a.width, a.height)),
              "scene.camera.clipyon = 1e30"]
    lo = [min(p[k] for m in scene["meshes"] for p in m["positions"]) for k in range(3)]
    hi = [max(p[k] for m in scene["meshes"] for p in m["positions"]) for k in range(3)]
    size = math.sqrt(sum((h - l) ** 2 for h, l in zip(hi, lo)))
    for k, m in enumerate(scene["materials"]):
        name = "m%d" % k
        lines += material_props(scene, m, k, name, tmp)
        if max(m["emission"]) > 0.0:
            lines += ["scene.materials.%s.emission = %s" % (name, vec(m["emission"])),
                      "scene.materials.%s.emission.gain = 1 1 1" % name,
                      "scene.materials.%s.emission.gain.normalizebycolor = 0" % name,
                      "scene.materials.%s.emission.power = 0" % name,
                      "scene.materials.%s.emission.efficency = 0" % name,
                      "scene.materials.%s.emission.directlightsampling.type = %s" % (name, a.mesh_dls.upper())]
            if a.mesh_lights == "dls-only":  # after a bounce, reached by light sampling alone
                lines += ["scene.materials.%s.visibility.indirect.%s.enable = 0" % (name, e)
                          for e in ("diffuse", "glossy", "specular")]
    for i, mesh in enumerate(scene["meshes"]):
        m = scene["materials"][mesh["material"]]
        copies = [("s%d" % i, mesh["positions"], mesh["triangles"], mesh["normals"])]
        if m["double_sided"] and (max(m["emission"]) > 0.0 or m["model"] != "lambert"):
            # LuxCore's area lights emit from the front only, and its glossy2 coats the front only (its
            # `doublesided` samples no coat on the back): the back side is a flipped copy just behind.
            pos = [list(p) for p in mesh["positions"]]
            shift = [[0.0, 0.0, 0.0] for _ in pos]
            for i0, i1, i2 in mesh["triangles"]:
                e = convert.cross(convert.sub(pos[i1], pos[i0]), convert.sub(pos[i2], pos[i0]))
                for v in (i0, i1, i2):
                    shift[v] = [s + x for s, x in zip(shift[v], e)]
            back = []
            for p, s in zip(pos, shift):
                n = math.sqrt(convert.dot(s, s)) or 1.0
                back.append([x - 1e-5 * size * y / n for x, y in zip(p, s)])
            flipped = [(i0, i2, i1) for i0, i1, i2 in mesh["triangles"]]
            normals = None if mesh["normals"] is None else [[-x for x in n] for n in mesh["normals"]]
            copies.append(("s%db" % i, back, flipped, normals))
        for shape, positions, tris, normals in copies:
            path = os.path.join(tmp, shape + ".ply")
            write_ply(path, positions, tris, normals, mesh["uvs"])
            lines += ["scene.shapes.%s.type = mesh" % shape, 'scene.shapes.%s.ply = "%s"' % (shape, path),
                      "scene.objects.o%s.shape = %s" % (shape, shape),
                      "scene.objects.o%s.material = m%d" % (shape, mesh["material"])]
    for i, light in enumerate(scene["lights"]):
        name = "scene.lights.l%d" % i
        if light["kind"] == "directional":
            lines += [name + ".type = sharpdistant", name + ".direction = " + vec(light["direction"]),
                      name + ".color = " + vec(light["intensity"]), name + ".gain = 1 1 1"]
            continue
        lines += [name + ".type = " + light["kind"], name + ".position = " + vec(light["position"]),
                  name + ".color = " + vec([4.0 * math.pi * v for v in light["intensity"]]),
                  name + ".gain = 1 1 1", name + ".power = 0", name + ".efficency = 0"]
        if light["kind"] == "spot":
            target = [p + d for p, d in zip(light["position"], light["direction"])]
            lines += [name + ".target = " + vec(target),
                      name + ".coneangle = %.9g" % math.degrees(light["outer_cone"]),
                      name + ".conedeltaangle = %.9g" % math.degrees(light["outer_cone"] - light["inner_cone"])]
    return "\n".join(lines) + "\n"


def config_props(a):
    lines = ["renderengine.type = %s" % a.engine.upper(), "sampler.type = SOBOL", "renderengine.seed = %d" % a.seed,
             "native.threads.count = %d" % a.threads,
             "path.pathdepth.total = 1024", "path.pathdepth.diffuse = 1024", "path.pathdepth.glossy = 1024",
             "path.pathdepth.specular = 1024", "path.clamping.variance.maxvalue = 0",
             "path.forceblackbackground.enable = 0",
             "film.width = %d" % a.width, "film.height = %d" % a.height,
             "film.filter.type = BOX", "film.filter.width = 0.5",
             "film.imagepipelines.0.0.type = NOP",
             "lightstrategy.type = %s" % a.light_strategy,
             "batch.haltthreshold = -1", "batch.haltnoisethreshold = -1"]
    if a.engine == "pathocl":  # every OpenCL device, no native CPU threads beside them
        lines += ["opencl.cpu.use = 1", "opencl.gpu.use = 1", "opencl.native.threads.count = 0"]
    if a.spp > 0:
        lines.append("batch.haltspp = %d" % a.spp)  # --time: main() stops the session itself
    if a.photongi:
        lines += ["path.photongi.sampler.type = METROPOLIS", "path.photongi.indirect.enabled = 1",
                  "path.photongi.caustic.enabled = 0"]
    return "\n".join(lines) + "\n"


def main():
    a = parse_args()
    t0 = time.perf_counter()
    scene = convert.load(a.scene)
    for w in scene["warnings"]:
        print("luxcore_peer: warning:", w, file=sys.stderr)
    tmp = tempfile.mkdtemp(prefix="luxcore-peer-")
    log = open(a.out + ".luxcore.log", "w")

    def log_line(msg):
        log.write(msg + "\n")
        log.flush()
    pyluxcore.Init(log_line)
    props = pyluxcore.Properties()
    props.SetFromString(scene_props(scene, a, tmp))
    lux_scene = pyluxcore.Scene()
    lux_scene.Parse(props)
    cfg_props = pyluxcore.Properties()
    cfg_props.SetFromString(config_props(a))
    config = pyluxcore.RenderConfig(cfg_props, lux_scene)
    session = pyluxcore.RenderSession(config)
    session.Start()
    # The clock of the budget starts at the first pass: LuxCore builds the DLS and PhotonGI caches in
    # its render threads after Start(), and counts them in its own time (and in batch.halttime, which
    # a PhotonGI build then uses up before the first sample). So the budget is kept here: set-up is
    # the wall time until the first pass is seen (polled every 20 ms), rendering the time from there
    # to the stop plus the first pass's share.
    t_first = passes_first = None
    while True:
        time.sleep(0.02)
        session.UpdateStats()
        stats = session.GetStats()
        passes = stats.Get("stats.renderengine.pass").GetInt()
        now = time.perf_counter()
        if t_first is None and passes > 0:
            t_first, passes_first = now, passes
        if a.time > 0 and t_first is not None and now - t_first >= a.time:
            break
        if session.HasDone():
            break
    session.Stop()
    t2 = time.perf_counter()
    session.UpdateStats()
    passes = session.GetStats().Get("stats.renderengine.pass").GetInt()
    elapsed = t2 - t_first
    # the passes done before t_first took about elapsed / (passes - passes_first) each
    render = elapsed * passes / max(passes - passes_first, 1)
    t1 = t2 - render
    film = session.GetFilm()
    buf = np.zeros(a.width * a.height * 3, dtype=np.float32)
    film.GetOutputFloat(pyluxcore.FilmOutputType.RGB, buf)
    img = np.flipud(buf.reshape(a.height, a.width, 3))  # LuxCore's first row is the bottom one
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                      {"RGB": np.ascontiguousarray(img)}) as f:
        f.write(a.out + ".exr")
    # PATHOCL compiles its kernels before the first pass (LuxCore logs each program's time): apart
    compile_s = sum(float(ms) for ms in re.findall(r"Kernels compilation time: ([0-9.]+) ?ms",
                                                    open(a.out + ".luxcore.log").read())) / 1000.0
    result = {"renderer": "LuxCore " + pyluxcore.Version(), "engine": a.engine.upper(), "photongi": a.photongi,
              "light_strategy": a.light_strategy, "mesh_dls": a.mesh_dls, "spp": passes,
              "render_seconds": render, "setup_seconds": t1 - t0 - compile_s, "kernel_compile_seconds": compile_s,
              "wall_seconds": t2 - t0,
              "threads": a.threads, "seed": a.seed}
    with open(a.out + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print("luxcore_peer:", json.dumps(result), flush=True)
    sys.stderr.flush()
    # pyluxcore's log handler thread aborts the interpreter's finalisation ("GIL is released"): leave
    # without it, everything written.
    os._exit(0)


main()
