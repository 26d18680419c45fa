#!/usr/bin/env python3
"""The scene conventions of the peer harness (issue 29), written once: glTF 2.0 -> a peer-neutral
scene that bench/peers/cycles_peer.py (Blender Cycles 5, bpy) and bench/peers/luxcore_peer.py
(LuxCoreRender 2.11, pyluxcore) each build their renderer's scene from.

Standard library only (the test suite runs it with Debian's python3; the peers' venv imports it).
The mapping follows bundlepath's loader (host/scene/gltf_loader.cpp, README "Scenes and the glTF
mapping"):

* triangles of the default scene (`scene`, else scene 0, else every root node), node transforms
  (matrix or TRS) applied, one copy per node that instances a mesh; TRIANGLES, TRIANGLE_STRIP and
  TRIANGLE_FAN; a mirroring transform swaps two corners so the front face stays front;
  zero-area triangles dropped; NORMAL carried by the inverse transpose (shading normals);
* materials: index 0 is the default (kd 0.8 grey), file material i is at i + 1, each in one of three
  models, as the loader reads it (`model`):
  - "phong": `extras.phong` with a lobe (max ks > 0): Modified Phong, kd Lambert + ks (n + 2)/(2 pi)
    cos^n of the mirror angle, kd and ks scaled down together where max(kd + ks) > 1 (the loader's
    energy cap); its textures are ignored, as by the loader;
  - "lambert": `extras.phong` without a lobe, or glTF metallic 0 with KHR_materials_specular's
    specular 0 (no Fresnel layer at all): kd = baseColor (times the base-colour texture);
  - "ggx": glTF's metallic-roughness BRDF (`ggx` true; kernels/shared/metallic_roughness.h): base colour
    (factor, and its texture: `texture` with `factor` = baseColorFactor), metallic, roughness
    (perceptual; alpha = roughness^2), the metallicRoughnessTexture (`mr_texture`: G times roughness,
    B times metallic, linear), ior (KHR_materials_ior, 1.5), specular weight and colour
    (KHR_materials_specular), dielectric f0 = min(((ior - 1)/(ior + 1))^2 specularColor, 1) (ior 0:
    f0 = 1), its Fresnel (f0 and f90 = 1) times the specular weight; kd = ks = 0, as the loader has them;
  textures are PNG/JPEG handed to the peers with one texcoord set per mesh (the base colour's, else the
  metallic-roughness texture's); KHR_texture_transform, emissive textures, specular textures and
  KHR_materials_transmission are reported, not carried;
* emission Le = emissiveFactor * KHR_materials_emissive_strength (W sr^-1 m^-2), from the front
  face, from both faces for `doubleSided` materials;
* KHR_lights_punctual: point and spot lights at the node's origin, pointing along its -z,
  intensity colour * candela / 683 (W/sr); directional lights (the sun): travelling along the
  node's -z, irradiance colour * lux / 683 (W/m^2); spot cones (inner, outer) as given;
* the camera: the first perspective camera met depth-first (yfov; the image aspect is the render's
  width / height), its position, forward (-z) and up (+y) in world space.

`python3 bench/peers/convert.py describe SCENE.gltf OUT.json` writes the peer-neutral description
(camera, per material: triangles, area, bounds, model, kd, ks, the metallic-roughness parameters of
a "ggx" one and the shininess of a "phong" one, emission; emitters with their power; lights with
their watts), which tests/e2e/test_peers_convert.cpp compares with bundlepath's own loader.
"""
import base64
import json
import math
import os
import struct
import sys

LUMENS_PER_WATT = 683.0

_COMPONENT = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
_COUNT = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_NORMALIZE = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}


class ConvertError(Exception):
    pass


# ---------------------------------------------------------------- small linear algebra (4x4, row-major)

def mat_identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def mat_from_node(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[float(m[c * 4 + r]) for c in range(4)] for r in range(4)]
    t = node.get("translation", [0.0, 0.0, 0.0])
    q = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    s = node.get("scale", [1.0, 1.0, 1.0])
    x, y, z, w = (float(v) for v in q)
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m = mat_identity()
    for i in range(3):
        for j in range(3):
            m[i][j] = r[i][j] * float(s[j])
        m[i][3] = float(t[i])
    return m


def transform_point(m, p):
    return [m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3)]


def transform_dir(m, d):
    return [m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2] for i in range(3)]


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
            m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def normal_matrix(m):
    """The inverse transpose of m's upper 3x3 (carries normals)."""
    d = det3(m)
    if d == 0.0:
        raise ConvertError("a node transform is singular")
    a = [[m[i][j] for j in range(3)] for i in range(3)]
    cof = [[0.0] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            r = [k for k in range(3) if k != i]
            c = [k for k in range(3) if k != j]
            minor = a[r[0]][c[0]] * a[r[1]][c[1]] - a[r[0]][c[1]] * a[r[1]][c[0]]
            cof[i][j] = (-1) ** (i + j) * minor / d
    return cof  # (A^-1)^T = cofactor / det


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(v):
    n = math.sqrt(dot(v, v))
    if n == 0.0:
        raise ConvertError("a zero direction")
    return [v[0] / n, v[1] / n, v[2] / n]


# ---------------------------------------------------------------- the file

def read_file(path):
    with open(path, "rb") as f:
        data = f.read()
    folder = os.path.dirname(os.path.abspath(path))
    if data[:4] == b"glTF":
        length = struct.unpack_from("<I", data, 8)[0]
        offset, gltf, bin_chunk = 12, None, None
        while offset + 8 <= length:
            size, kind = struct.unpack_from("<II", data, offset)
            chunk = data[offset + 8:offset + 8 + size]
            if kind == 0x4E4F534A:
                gltf = json.loads(chunk.decode("utf-8"))
            elif kind == 0x004E4942 and bin_chunk is None:
                bin_chunk = chunk
            offset += 8 + size
        if gltf is None:
            raise ConvertError(path + ": a .glb without a JSON chunk")
    else:
        gltf, bin_chunk = json.loads(data.decode("utf-8")), None
    buffers = []
    for i, b in enumerate(gltf.get("buffers", [])):
        uri = b.get("uri")
        if uri is None:
            if bin_chunk is None:
                raise ConvertError("%s: buffer %d has no uri and the file no BIN chunk" % (path, i))
            buffers.append(bin_chunk)
        elif uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(folder, uri), "rb") as f:
                buffers.append(f.read())
    return gltf, buffers, folder


class Reader:
    def __init__(self, gltf, buffers):
        self.gltf, self.buffers = gltf, buffers

    def view_bytes(self, index):
        v = self.gltf["bufferViews"][index]
        start = v.get("byteOffset", 0)
        return self.buffers[v["buffer"]][start:start + v["byteLength"]], v.get("byteStride")

    def accessor(self, index):
        """The accessor's elements as a flat list of floats/ints (normalized integers as floats)."""
        acc = self.gltf["accessors"][index]
        fmt, size = _COMPONENT[acc["componentType"]]
        comps = _COUNT[acc["type"]]
        count = acc["count"]
        out = [0] * (count * comps)
        if "bufferView" in acc:
            data, stride = self.view_bytes(acc["bufferView"])
            offset = acc.get("byteOffset", 0)
            stride = stride or size * comps
            if stride == size * comps:
                out = list(struct.unpack_from("<%d%s" % (count * comps, fmt), data, offset))
            else:
                one = struct.Struct("<%d%s" % (comps, fmt))
                out = []
                for i in range(count):
                    out.extend(one.unpack_from(data, offset + i * stride))
        sparse = acc.get("sparse")
        if sparse:
            n = sparse["count"]
            ifmt, isize = _COMPONENT[sparse["indices"]["componentType"]]
            idata, _ = self.view_bytes(sparse["indices"]["bufferView"])
            idx = struct.unpack_from("<%d%s" % (n, ifmt), idata, sparse["indices"].get("byteOffset", 0))
            vdata, _ = self.view_bytes(sparse["values"]["bufferView"])
            vals = struct.unpack_from("<%d%s" % (n * comps, fmt), vdata, sparse["values"].get("byteOffset", 0))
            out = list(out)
            for k, i in enumerate(idx):
                out[i * comps:(i + 1) * comps] = vals[k * comps:(k + 1) * comps]
        if acc.get("normalized") and acc["componentType"] in _NORMALIZE:
            s = _NORMALIZE[acc["componentType"]]
            out = [max(v / s, -1.0) for v in out]
        return out, comps


def phong_extras(mat):
    extras = mat.get("extras")
    return extras.get("phong") if isinstance(extras, dict) else None


def texture_ref(info, name, what, warnings):
    """A glTF textureInfo as the peers read it: index and texcoord set (KHR_texture_transform dropped)."""
    if info is None:
        return None
    if "KHR_texture_transform" in info.get("extensions", {}):
        warnings.append("%s: KHR_texture_transform of its %s ignored by the peers" % (name, what))
    return {"texture": info["index"], "texcoord": info.get("texCoord", 0)}


def read_material(mat, index, warnings):
    """One glTF material as the loader reads it (host/scene/gltf_loader.cpp, read_materials), in one of
    three models: "phong" (extras.phong with a lobe: kd, ks, shininess), "lambert" (kd: extras.phong
    without a lobe, or metallic 0 with specular 0), "ggx" (glTF's metallic-roughness BRDF)."""
    name = mat.get("name") or "material %d" % index
    out = {"name": name, "double_sided": bool(mat.get("doubleSided", False)), "texture": None,
           "mr_texture": None, "textured": False, "ggx": False, "kd": [0.0] * 3, "ks": [0.0] * 3, "shininess": 1.0}
    ext = mat.get("extensions", {})
    phong = phong_extras(mat)
    pbr = mat.get("pbrMetallicRoughness", {})
    if phong is not None:
        out["kd"] = [float(v) for v in phong.get("kd", [0.0, 0.0, 0.0])]
        out["ks"] = [float(v) for v in phong.get("ks", [0.0, 0.0, 0.0])]
        out["shininess"] = float(phong.get("shininess", 1.0))
        peak = max(kd + ks for kd, ks in zip(out["kd"], out["ks"]))
        if peak > 1.0:  # the loader's energy cap (docs/design.md §6)
            out["kd"] = [v / peak for v in out["kd"]]
            out["ks"] = [v / peak for v in out["ks"]]
        out["model"] = "phong" if max(out["ks"]) > 0.0 else "lambert"
        if "baseColorTexture" in pbr or "metallicRoughnessTexture" in pbr or "emissiveTexture" in mat:
            warnings.append("%s: extras.phong wins; its textures are ignored (as by the loader)" % name)
    else:
        base = [float(v) for v in pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])[:3]]
        metallic = float(pbr.get("metallicFactor", 1.0))
        roughness = float(pbr.get("roughnessFactor", 1.0))
        spec = ext.get("KHR_materials_specular", {})
        sf = float(spec.get("specularFactor", 1.0))
        scf = [float(v) for v in spec.get("specularColorFactor", [1.0, 1.0, 1.0])]
        # KHR_materials_ior: 0 means f0 = 1; dielectric f0 = min(f0(ior) specularColor, 1), its
        # Fresnel (f0 and f90 = 1) times specular (host/scene/gltf_loader.cpp, read_metallic_roughness)
        ior = float(ext.get("KHR_materials_ior", {}).get("ior", 1.5))
        f0_ior = 1.0 if ior == 0.0 else ((ior - 1.0) / (ior + 1.0)) ** 2
        out["ggx"] = not (metallic == 0.0 and sf == 0.0)
        out["model"] = "ggx" if out["ggx"] else "lambert"
        out["base_color"], out["metallic"], out["roughness"] = base, metallic, roughness
        out["ior"], out["specular_weight"], out["specular_color"] = ior, sf, scf
        out["dielectric_f0"] = [min(f0_ior * c, 1.0) for c in scf]
        if not out["ggx"]:
            out["kd"] = list(base)  # no Fresnel layer at all: exactly Lambert
        # textured as the loader counts it: f or emission read from a texture
        out["textured"] = any(k in pbr for k in ("baseColorTexture", "metallicRoughnessTexture")) or \
            "emissiveTexture" in mat
        out["texture"] = texture_ref(pbr.get("baseColorTexture"), name, "baseColorTexture", warnings)
        if out["texture"] is not None:
            out["texture"]["factor"] = list(base)  # the colour the texel multiplies (kd or baseColor)
        if out["ggx"]:
            out["mr_texture"] = texture_ref(pbr.get("metallicRoughnessTexture"), name, "metallicRoughnessTexture",
                                            warnings)
        for key in ("specularTexture", "specularColorTexture"):
            if key in spec:
                warnings.append("%s: KHR_materials_specular.%s ignored (as by the loader)" % (name, key))
        if "KHR_materials_transmission" in ext:
            warnings.append("%s: KHR_materials_transmission ignored by the peers (rendered opaque)" % name)
    strength = float(ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0))
    out["emission"] = [strength * float(v) for v in mat.get("emissiveFactor", [0.0, 0.0, 0.0])]
    if "emissiveTexture" in mat and phong is None:
        warnings.append("%s: emissiveTexture ignored by the peers" % name)
    return out


def phong_ggx_alpha(shininess):
    """The GGX alpha the peers draw a Modified Phong lobe of exponent n with (approximate): the Phong lobe
    cos^n of the mirror angle is close to the Blinn lobe cos^4n of the half-angle, and that to GGX's
    alpha = sqrt(2 / (4n + 2)) (Walter et al. 2007's Blinn-Beckmann correspondence); the same mapping
    as bench/make_rooms.cpp --ggx. Half-widths at half maximum, at normal incidence: GGX's is 0.77
    times Phong's (sqrt(2 / (n + 2)) would make it 1.5 times)."""
    return math.sqrt(2.0 / (4.0 * max(shininess, 0.0) + 2.0))


def scene_roots(gltf):
    scenes = gltf.get("scenes", [])
    if scenes:
        return scenes[gltf.get("scene", 0)].get("nodes", [])
    children = {c for n in gltf.get("nodes", []) for c in n.get("children", [])}
    return [i for i in range(len(gltf.get("nodes", []))) if i not in children]


def triangle_corners(mode, n):
    if mode == 4:
        return [(i, i + 1, i + 2) for i in range(0, n - n % 3, 3)]
    if mode == 5:
        return [(i, i + 1, i + 2) if i % 2 == 0 else (i + 1, i, i + 2) for i in range(n - 2)]
    if mode == 6:
        return [(0, i, i + 1) for i in range(1, n - 1)]
    return None


def load(path):
    """glTF -> the peer-neutral scene (a dict; see the module's docstring)."""
    gltf, buffers, folder = read_file(path)
    reader = Reader(gltf, buffers)
    warnings = []
    materials = [{"name": "default", "model": "lambert", "kd": [0.8, 0.8, 0.8], "ks": [0.0, 0.0, 0.0],
                  "shininess": 1.0, "ggx": False, "emission": [0.0, 0.0, 0.0], "double_sided": False,
                  "texture": None, "mr_texture": None}]
    for i, m in enumerate(gltf.get("materials", [])):
        materials.append(read_material(m, i, warnings))
    meshes, lights, camera = [], [], None
    lights_ext = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    dropped = 0

    def visit(index, parent):
        nonlocal camera, dropped
        node = gltf["nodes"][index]
        world = mat_mul(parent, mat_from_node(node))
        if "mesh" in node:
            mirror = det3(world) < 0.0
            nmat = None
            for p, prim in enumerate(gltf["meshes"][node["mesh"]]["primitives"]):
                mode = prim.get("mode", 4)
                attrs = prim.get("attributes", {})
                if "POSITION" not in attrs:
                    continue
                pos, _ = reader.accessor(attrs["POSITION"])
                nverts = len(pos) // 3
                if "indices" in prim:
                    idx, _ = reader.accessor(prim["indices"])
                else:
                    idx = list(range(nverts))
                corners = triangle_corners(mode, len(idx))
                if corners is None:
                    warnings.append("skipped a primitive of mode %d" % mode)
                    continue
                wpos = [transform_point(world, pos[3 * i:3 * i + 3]) for i in range(nverts)]
                normals = None
                if "NORMAL" in attrs:
                    nrm, _ = reader.accessor(attrs["NORMAL"])
                    nmat = nmat or normal_matrix(world)
                    normals = []
                    for i in range(nverts):
                        v = [sum(nmat[r][c] * nrm[3 * i + c] for c in range(3)) for r in range(3)]
                        n = math.sqrt(dot(v, v))
                        normals.append([x / n for x in v] if n > 0.0 else [0.0, 0.0, 0.0])
                material = prim.get("material", -1) + 1
                mat = materials[material]
                # one texcoord set per mesh: the base colour's, else the metallic-roughness texture's
                tex = mat["texture"] or mat["mr_texture"]
                uvs = None
                if tex is not None:
                    if mat["texture"] and mat["mr_texture"] and mat["mr_texture"]["texcoord"] != tex["texcoord"]:
                        warnings.append("%s: metallicRoughnessTexture read through TEXCOORD_%d by the peers"
                                        % (mat["name"], tex["texcoord"]))
                    key = "TEXCOORD_%d" % tex["texcoord"]
                    if key in attrs:
                        uv, _ = reader.accessor(attrs[key])
                        uvs = [uv[2 * i:2 * i + 2] for i in range(nverts)]
                    else:
                        uvs = [[0.0, 0.0]] * nverts
                tris = []
                for a, b, c in corners:
                    i0, i1, i2 = idx[a], idx[b], idx[c]
                    if mirror:
                        i1, i2 = i2, i1
                    e = cross(sub(wpos[i1], wpos[i0]), sub(wpos[i2], wpos[i0]))
                    if dot(e, e) == 0.0:
                        dropped += 1
                        continue
                    tris.append((i0, i1, i2))
                if tris:
                    meshes.append({"name": "%s/%d" % (node.get("name", "node %d" % index), p), "material": material,
                                   "positions": wpos, "normals": normals, "uvs": uvs, "triangles": tris})
        if "camera" in node and camera is None:
            cam = gltf["cameras"][node["camera"]]
            if cam.get("type") == "perspective":
                persp = cam["perspective"]
                camera = {"name": cam.get("name", ""), "position": transform_point(world, [0.0, 0.0, 0.0]),
                          "forward": normalize(transform_dir(world, [0.0, 0.0, -1.0])),
                          "up": normalize(transform_dir(world, [0.0, 1.0, 0.0])),
                          "yfov": float(persp["yfov"]), "aspect": float(persp.get("aspectRatio", 0.0))}
                # up orthogonal to forward (a sheared node): Gram-Schmidt
                f, u = camera["forward"], camera["up"]
                camera["up"] = normalize(sub(u, [dot(u, f) * x for x in f]))
        light_ref = node.get("extensions", {}).get("KHR_lights_punctual")
        if light_ref is not None:
            spec = lights_ext[light_ref["light"]]
            kind = spec["type"]
            colour = [float(v) for v in spec.get("color", [1.0, 1.0, 1.0])]
            intensity = float(spec.get("intensity", 1.0))
            light = {"name": spec.get("name", ""), "kind": kind,
                     "intensity": [c * intensity / LUMENS_PER_WATT for c in colour],
                     "position": transform_point(world, [0.0, 0.0, 0.0]),
                     "direction": normalize(transform_dir(world, [0.0, 0.0, -1.0]))}
            if kind == "spot":
                s = spec.get("spot", {})
                light["inner_cone"] = float(s.get("innerConeAngle", 0.0))
                light["outer_cone"] = float(s.get("outerConeAngle", math.pi / 4))
            lights.append(light)
        for c in node.get("children", []):
            visit(c, world)

    for root in scene_roots(gltf):
        visit(root, mat_identity())
    if dropped:
        warnings.append("dropped %d degenerate (zero-area) triangle(s)" % dropped)
    if not meshes:
        raise ConvertError(path + ": no triangles")
    if camera is None:
        raise ConvertError(path + ": no perspective camera (the peers need the file's view)")
    textures = {}
    for m in materials:
        for t in (m["texture"], m["mr_texture"]):
            if t is not None and t["texture"] not in textures:
                textures[t["texture"]] = read_texture(gltf, reader, folder, t["texture"])
    return {"source": os.path.abspath(path), "camera": camera, "materials": materials, "meshes": meshes,
            "lights": lights, "textures": textures, "warnings": warnings}


def read_texture(gltf, reader, folder, index):
    """A texture's image bytes, type, and the sampler's filter and wraps (glTF's numbers)."""
    tex = gltf["textures"][index]
    image = gltf["images"][tex["source"]]
    if "bufferView" in image:
        data, _ = reader.view_bytes(image["bufferView"])
        mime = image.get("mimeType", "image/png")
    elif image["uri"].startswith("data:"):
        head, payload = image["uri"].split(",", 1)
        data, mime = base64.b64decode(payload), head[5:].split(";")[0]
    else:
        with open(os.path.join(folder, image["uri"]), "rb") as f:
            data = f.read()
        mime = "image/jpeg" if image["uri"].lower().endswith((".jpg", ".jpeg")) else "image/png"
    sampler = gltf.get("samplers", [])[tex["sampler"]] if "sampler" in tex else {}
    return {"bytes": data, "mime": mime, "nearest": sampler.get("magFilter") == 9728,
            "wrap_s": sampler.get("wrapS", 10497), "wrap_t": sampler.get("wrapT", 10497)}


def write_texture(scene, index, folder):
    """Writes texture `index` of `scene` into `folder`; returns its path."""
    t = scene["textures"][index]
    path = os.path.join(folder, "texture-%d.%s" % (index, "jpg" if t["mime"] == "image/jpeg" else "png"))
    with open(path, "wb") as f:
        f.write(t["bytes"])
    return path


# ---------------------------------------------------------------- what the peers are given, in numbers

def describe(scene):
    """The peer-neutral description: what every peer must render, in numbers a test can check."""
    mats = [dict({"name": m["name"], "model": m["model"], "kd": m["kd"], "ks": m["ks"], "emission": m["emission"],
                  "double_sided": m["double_sided"], "ggx": m["ggx"],
                  "textured": m.get("textured", False),
                  "triangles": 0, "area": 0.0, "vector_area": [0.0, 0.0, 0.0], "bounds": None},
                 **({k: m[k] for k in ("base_color", "metallic", "roughness", "ior", "specular_weight",
                                       "specular_color", "dielectric_f0")} if m["ggx"] else {}),
                 **({"metallic_roughness_texture": m["mr_texture"] is not None} if m["ggx"] else {}),
                 **({"shininess": m["shininess"]} if m["model"] == "phong" else {}))
            for m in scene["materials"]]
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for mesh in scene["meshes"]:
        d = mats[mesh["material"]]
        pos = mesh["positions"]
        for i0, i1, i2 in mesh["triangles"]:
            d["triangles"] += 1
            e = cross(sub(pos[i1], pos[i0]), sub(pos[i2], pos[i0]))
            d["area"] += 0.5 * math.sqrt(dot(e, e))
            d["vector_area"] = [v + 0.5 * x for v, x in zip(d["vector_area"], e)]  # the front faces' side
            b = d["bounds"] or [[math.inf] * 3, [-math.inf] * 3]
            for i in (i0, i1, i2):
                for k in range(3):
                    b[0][k] = min(b[0][k], pos[i][k])
                    b[1][k] = max(b[1][k], pos[i][k])
                    lo[k] = min(lo[k], pos[i][k])
                    hi[k] = max(hi[k], pos[i][k])
            d["bounds"] = b
    emitters = []
    for i, d in enumerate(mats):
        if d["triangles"] and max(d["emission"]) > 0.0:
            sides = 2.0 if d["double_sided"] else 1.0
            emitters.append({"material": i, "name": d["name"], "radiance": d["emission"],
                             "double_sided": d["double_sided"], "area": d["area"],
                             "power_w": [math.pi * sides * d["area"] * le for le in d["emission"]]})
    lights = []
    for light in scene["lights"]:
        out = dict(light)
        if light["kind"] in ("point", "spot"):
            out["watts"] = [4.0 * math.pi * v for v in light["intensity"]]  # Blender's watts, LuxCore's gain
        else:
            out["irradiance"] = light["intensity"]
        lights.append(out)
    return {"source": scene["source"], "camera": scene["camera"],
            "triangles": sum(d["triangles"] for d in mats), "bounds": [lo, hi],
            "materials": mats, "emitters": emitters, "lights": lights, "warnings": scene["warnings"]}


def main(argv):
    if len(argv) != 4 or argv[1] != "describe":
        sys.stderr.write("usage: convert.py describe SCENE.gltf|SCENE.glb OUT.json\n")
        return 2
    try:
        desc = describe(load(argv[2]))
    except (ConvertError, OSError, KeyError, IndexError, ValueError, struct.error) as e:
        sys.stderr.write("convert.py: %s: %s\n" % (argv[2], e))
        return 3
    with open(argv[3], "w") as f:
        json.dump(desc, f, indent=1)
    for w in desc["warnings"]:
        sys.stderr.write("convert.py: warning: %s\n" % w)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
