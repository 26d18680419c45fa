#!/usr/bin/env bash
# CTest make_rooms_output: the written camera has no zfar (glTF: an infinite projection; tinygltf's
# zfar 0 is invalid and makes Blender clip everything), in .glb and .gltf; --lambert writes ks = 0
# everywhere and keeps kd; --ggx writes metallic-roughness dielectrics with baseColor = kd, roughness
# from the Phong exponent where there is a lobe and 1 where not, and no extras.phong, and with
# --roughness R that roughness wherever there is a lobe, all else the same; --rooms R keeps
# the house (materials, lights, camera, extent) and only tessellates it finer, within 2 % of the
# target count, and --rooms at the default grid writes the same bytes; bad arguments exit 2 with the
# usage.
# Usage: bench/make_rooms_test.sh MAKE_ROOMS WORKDIR
set -euo pipefail
tool=$1 dir=$2
mkdir -p "$dir"
"$tool" 3000 "$dir/plain.glb" 2>/dev/null
"$tool" 3000 "$dir/lambert.gltf" --lambert 2>/dev/null
"$tool" 3000 "$dir/lambert.glb" --lambert --seed 1 2>/dev/null
"$tool" 3000 "$dir/ggx.gltf" --ggx 2>/dev/null
"$tool" 3000 "$dir/ggx-rough.gltf" --ggx --roughness 0.15 2>/dev/null
"$tool" 3000 "$dir/plain-r1.glb" --rooms 1 2>/dev/null
"$tool" 30000 "$dir/fine-r1.glb" --rooms 1 2>/dev/null
"$tool" 100000 "$dir/fine-r2.glb" --rooms 2 2>/dev/null
"$tool" 16000 "$dir/plain-16000.glb" 2>/dev/null  # the default grid at 16000 triangles is 2x2
cmp "$dir/plain.glb" "$dir/plain-r1.glb" || { echo "make_rooms --rooms 1 (the default grid) changed the file" >&2; exit 1; }
python3 - "$dir" <<'PY'
import json, struct, sys
d = sys.argv[1]
def glb_json(path):
    b = open(path, "rb").read()
    magic, version, length = struct.unpack("<4sII", b[:12])
    assert magic == b"glTF" and version == 2 and length == len(b), (magic, version, length, len(b))
    n, kind = struct.unpack("<II", b[12:20])
    assert kind == 0x4E4F534A and n % 4 == 0, (hex(kind), n)
    m, bin_kind = struct.unpack("<II", b[20 + n:28 + n])
    assert bin_kind == 0x004E4942 and 28 + n + m == len(b), "BIN chunk"
    return json.loads(b[20:20 + n])
plain, lambert_glb = glb_json(f"{d}/plain.glb"), glb_json(f"{d}/lambert.glb")
lambert = json.load(open(f"{d}/lambert.gltf"))
for doc in (plain, lambert, lambert_glb):
    for cam in doc["cameras"]:
        p = cam["perspective"]
        assert "zfar" not in p, p
        assert p["znear"] > 0 and p["yfov"] > 0, p
phong = lambda doc: {m["name"]: m["extras"]["phong"] for m in doc["materials"]}
assert any(max(v["ks"]) > 0 for v in phong(plain).values()), "the plain house has Phong lobes"
for doc in (lambert, lambert_glb):
    for name, v in phong(doc).items():
        assert v["ks"] == [0.0, 0.0, 0.0], (name, v)
        assert v["kd"] == phong(plain)[name]["kd"], (name, v)
ggx = json.load(open(f"{d}/ggx.gltf"))
for m in ggx["materials"]:
    assert "extras" not in m, m
    pbr, v = m["pbrMetallicRoughness"], phong(plain)[m["name"]]
    assert pbr["metallicFactor"] == 0.0 and pbr["baseColorFactor"][:3] == v["kd"], (m, v)
    lobe = max(v["ks"]) > 0
    expected = (2.0 / (4.0 * v["shininess"] + 2.0)) ** 0.25 if lobe else 1.0
    assert abs(pbr.get("roughnessFactor", 1.0) - expected) < 1e-6, (m, expected)
assert any(m["pbrMetallicRoughness"].get("roughnessFactor", 1.0) < 0.5 for m in ggx["materials"]), "glossy"
rough = json.load(open(f"{d}/ggx-rough.gltf"))
for m, g in zip(rough["materials"], ggx["materials"]):
    lobe = max(phong(plain)[m["name"]]["ks"]) > 0
    r = m["pbrMetallicRoughness"].get("roughnessFactor", 1.0)
    assert abs(r - (0.15 if lobe else 1.0)) < 1e-6, (m, lobe)
    assert {**m, "pbrMetallicRoughness": {}} == {**g, "pbrMetallicRoughness": {}}, (m, g)

def house(path):
    doc = glb_json(path)
    acc = doc["accessors"]
    prims = doc["meshes"][0]["primitives"]
    per_material = {doc["materials"][p["material"]]["name"]: acc[p["attributes"]["POSITION"]] for p in prims}
    lo = [min(a["min"][i] for a in per_material.values()) for i in range(3)]
    hi = [max(a["max"][i] for a in per_material.values()) for i in range(3)]
    triangles = sum(a["count"] for a in per_material.values()) // 3
    return doc, per_material, triangles, (lo, hi)
for fine_path, plain_path, target in ((f"{d}/fine-r1.glb", f"{d}/plain.glb", 30000),
                                      (f"{d}/fine-r2.glb", f"{d}/plain-16000.glb", 100000)):
    fine, fine_mats, fine_n, fine_box = house(fine_path)
    plain, plain_mats, plain_n, plain_box = house(plain_path)
    assert abs(fine_n - target) <= 0.02 * target, (fine_path, fine_n, target)
    assert fine_n > 5 * plain_n, (fine_path, fine_n, plain_n)
    assert fine["materials"] == plain["materials"], fine_path
    assert fine["cameras"] == plain["cameras"], fine_path
    camera = lambda doc: [n for n in doc["nodes"] if "camera" in n]
    assert camera(fine) == camera(plain), (camera(fine), camera(plain))
    assert fine_mats["light"] == plain_mats["light"], (fine_mats["light"], plain_mats["light"])  # same panels
    assert fine_box == plain_box, (fine_box, plain_box)
print("make_rooms output OK")
PY
for args in "3000 $dir/x.glb --rooms 0" "3000 $dir/x.glb --rooms x" "3000 $dir/x.glb --rooms" "3000 $dir/x.glb --lambert --ggx" "abc $dir/x.glb" "3000 $dir/x.glb --bogus" "3000" "3000 $dir/x.obj" "3000 $dir/x.glb --seed" "-5 $dir/x.glb" "3000 $dir/x.glb --roughness 0.2" "3000 $dir/x.glb --ggx --roughness 1.5" "3000 $dir/x.glb --ggx --roughness" "3000 $dir/x.glb --ggx --roughness a"; do
  rc=0
  # shellcheck disable=SC2086
  msg=$("$tool" $args 2>&1) || rc=$?
  if [ $rc -ne 2 ] || [[ $msg != *usage:* ]]; then
    echo "make_rooms $args: exit $rc, expected 2 with the usage: $msg" >&2
    exit 1
  fi
done
echo "make_rooms bad arguments OK"
