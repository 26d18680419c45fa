// Writes the procedural rooms scene (bp::make_rooms_scene, host/scene/procedural.h) as a glTF
// binary (.glb) or .gltf, so `bundlepath render` can draw it: materials as extras.phong (or glTF
// metallic-roughness, --ggx) plus emissiveFactor / KHR_materials_emissive_strength, double-sided
// walls as doubleSided, the camera as
// a node. The file is read back with the renderer's own loader and checked (triangle count,
// materials, camera) before the tool reports success. The camera has no zfar (an infinite
// projection): tinygltf always writes one, 0 when unset, which is not valid glTF (zfar > znear) and
// makes Blender clip everything, so the written JSON is edited before it reaches the file.
// Usage: make_rooms TRIANGLES OUT.glb|OUT.gltf [--seed N] [--rooms R] [--lambert | --ggx [--roughness R]]
//   --rooms R: R x R rooms whatever TRIANGLES is, so one house (layout, lights, camera) can be
//   written at several triangle counts, the extra triangles from finer tessellation of the same
//   surfaces; R equal to the default grid writes the same bytes as leaving it out.
//   --lambert: every material pure Lambert (ks = 0, kd kept): the "Lambert house".
//   --ggx: glTF's own metallic-roughness materials (no extras.phong): the "GGX house" (set_ggx_material);
//   --roughness R: every glossy material of it at roughness R (the roughness sweep, bench/README.md).
#include "scene/tinygltf.h"

#include "scene/gltf_loader.h"
#include "scene/procedural.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

tinygltf::Value rgb_value(const glm::vec3& c) {
  return tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(c.x)), tinygltf::Value(double(c.y)),
                                                 tinygltf::Value(double(c.z))});
}

// The GGX house's material for a Phong one: a dielectric (metallic 0, glTF's default ior 1.5) with
// baseColor = kd; a Phong lobe of exponent n as the Blinn lobe of exponent 4n it is close to, and
// that as GGX's α = sqrt(2 / (4n + 2)) (Walter et al. 2007's Beckmann-Blinn correspondence),
// roughness = sqrt(α) (glTF: α = roughness²); a material without a lobe (ks = 0) at roughness 1.
// The floor (n = 20) gets roughness 0.39, the furniture (n = 40) 0.33; `roughness` >= 0 replaces
// every lobe's (make_rooms --roughness: the same house glossier or rougher).
void set_ggx_material(tinygltf::Material& out, const bp::SceneMaterial& m, double roughness) {
  out.pbrMetallicRoughness.baseColorFactor = {m.kd.x, m.kd.y, m.kd.z, 1.0};
  out.pbrMetallicRoughness.metallicFactor = 0.0;
  const bool lobe = std::max(m.ks.x, std::max(m.ks.y, m.ks.z)) > 0.0f;
  const double from_shininess = std::sqrt(std::sqrt(2.0 / (4.0 * m.shininess + 2.0)));
  out.pbrMetallicRoughness.roughnessFactor = lobe ? (roughness >= 0.0 ? roughness : from_shininess) : 1.0;
}

void set_phong_material(tinygltf::Material& out, const bp::SceneMaterial& m) {
  tinygltf::Value::Object phong;
  phong["kd"] = rgb_value(m.kd);
  phong["ks"] = rgb_value(m.ks);
  phong["shininess"] = tinygltf::Value(double(m.shininess));
  out.extras = tinygltf::Value(tinygltf::Value::Object{{"phong", tinygltf::Value(phong)}});
}

tinygltf::Model to_gltf(const bp::Scene& scene, bool ggx, double roughness) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "bundlepath bench/make_rooms (" + scene.source + ")";
  bool emissive_strength = false;
  for (const bp::SceneMaterial& m : scene.materials) {
    tinygltf::Material out;
    out.name = m.name;
    out.doubleSided = m.double_sided;
    if (ggx) set_ggx_material(out, m, roughness);
    else set_phong_material(out, m);
    const float peak = std::max(m.emission.x, std::max(m.emission.y, m.emission.z));
    if (peak > 0.0f) {
      const float strength = std::max(1.0f, peak);  // emissiveFactor stays in [0, 1]
      out.emissiveFactor = {m.emission.x / strength, m.emission.y / strength, m.emission.z / strength};
      if (strength > 1.0f) {
        out.extensions["KHR_materials_emissive_strength"] =
            tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", tinygltf::Value(double(strength))}});
        emissive_strength = true;
      }
    }
    model.materials.push_back(out);
  }
  if (emissive_strength) model.extensionsUsed.push_back("KHR_materials_emissive_strength");

  // One buffer: per material, its triangles' positions (unindexed, 3 vertices each).
  tinygltf::Buffer buffer;
  tinygltf::Mesh mesh;
  mesh.name = "rooms";
  for (std::size_t mat = 0; mat < scene.materials.size(); ++mat) {
    std::vector<float> positions;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const bp::SceneTriangle& t : scene.triangles) {
      if (t.material != mat) continue;
      for (const glm::vec3& p : t.p) {
        positions.insert(positions.end(), {p.x, p.y, p.z});
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
    }
    if (positions.empty()) continue;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.data.size();
    view.byteLength = positions.size() * sizeof(float);
    view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
    const auto* bytes = reinterpret_cast<const unsigned char*>(positions.data());
    buffer.data.insert(buffer.data.end(), bytes, bytes + view.byteLength);
    model.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = int(model.bufferViews.size()) - 1;
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.type = TINYGLTF_TYPE_VEC3;
    accessor.count = positions.size() / 3;
    accessor.minValues = {lo.x, lo.y, lo.z};
    accessor.maxValues = {hi.x, hi.y, hi.z};
    model.accessors.push_back(accessor);
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = int(model.accessors.size()) - 1;
    primitive.material = int(mat);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(primitive);
  }
  model.buffers.push_back(buffer);
  model.meshes.push_back(mesh);

  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.name = "view";
  camera.perspective.yfov = scene.camera.yfov;
  camera.perspective.aspectRatio = 1.0;
  camera.perspective.znear = 0.01;
  model.cameras.push_back(camera);

  tinygltf::Node mesh_node;
  mesh_node.mesh = 0;
  mesh_node.name = "rooms";
  tinygltf::Node camera_node;
  camera_node.camera = 0;
  camera_node.name = "camera";
  const glm::vec3 f = glm::normalize(scene.camera.forward);
  const glm::vec3 r = glm::normalize(glm::cross(f, scene.camera.up));
  const glm::vec3 u = glm::cross(r, f);
  const glm::vec3 p = scene.camera.position;
  camera_node.matrix = {r.x, r.y, r.z, 0, u.x, u.y, u.z, 0, -f.x, -f.y, -f.z, 0, p.x, p.y, p.z, 1};
  model.nodes = {mesh_node, camera_node};
  tinygltf::Scene root;
  root.nodes = {0, 1};
  model.scenes.push_back(root);
  model.defaultScene = 0;
  return model;
}

// The glTF JSON with every perspective camera's zfar removed (glTF: absent zfar = infinite projection).
std::string without_zfar(const std::string& json_text) {
  nlohmann::json doc = nlohmann::json::parse(json_text);
  if (doc.contains("cameras"))
    for (auto& camera : doc["cameras"])
      if (camera.contains("perspective")) camera["perspective"].erase("zfar");
  return doc.dump();
}

std::uint32_t read_u32(const std::string& s, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

void append_u32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

// tinygltf's output with the JSON edited by without_zfar: a .gltf is the JSON itself; a .glb is a
// 12-byte header, the JSON chunk (padded with spaces to 4 bytes) and the BIN chunk, rebuilt here.
std::string fix_camera(const std::string& written, bool binary) {
  if (!binary) return without_zfar(written);
  if (written.size() < 20 || written.compare(0, 4, "glTF") != 0) throw std::runtime_error("not a GLB stream");
  const std::uint32_t json_length = read_u32(written, 12);
  std::string json = without_zfar(written.substr(20, json_length));
  while (json.size() % 4) json += ' ';
  const std::string rest = written.substr(20 + json_length);  // the BIN chunk, header included
  std::string out = "glTF";
  append_u32(out, 2);
  append_u32(out, std::uint32_t(12 + 8 + json.size() + rest.size()));
  append_u32(out, std::uint32_t(json.size()));
  append_u32(out, 0x4E4F534Au);  // "JSON"
  out += json;
  out += rest;
  return out;
}

const char kUsage[] =
    "usage: make_rooms TRIANGLES OUT.glb|OUT.gltf [--seed N] [--rooms R] [--lambert | --ggx [--roughness R]]\n"
    "  TRIANGLES  about how many triangles the rooms are tessellated to (a positive integer)\n"
    "  --seed N   the layout's seed [1]\n"
    "  --rooms R  R x R rooms, the same house at any TRIANGLES (finer tessellation)\n"
    "             [round(sqrt(TRIANGLES / 4000)): more triangles, more rooms]\n"
    "  --lambert  every material pure Lambert (ks = 0, kd kept)\n"
    "  --ggx      glTF metallic-roughness materials (GGX; the Phong lobes as roughness)\n"
    "  --roughness R  with --ggx: every glossy material (floor, furniture) at roughness R in [0, 1]\n";

// The default grid at the largest TRIANGLES (2^32) is 1036 rooms per side.
constexpr std::uint64_t kMaxRoomsPerSide = 1024;

bool parse_count(const char* text, std::uint64_t& value) {
  const char* end = text + std::strlen(text);
  auto [ptr, ec] = std::from_chars(text, end, value);
  return ec == std::errc() && ptr == end && end != text;
}

int usage_error(const std::string& message) {
  std::fprintf(stderr, "make_rooms: %s\n%s", message.c_str(), kUsage);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  std::uint32_t seed = 1;
  int rooms = 0;  // 0: make_rooms_scene's default for the triangle count
  bool lambert = false, ggx = false;
  double roughness = -1.0;  // < 0: from the Phong lobes
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--lambert") {
      lambert = true;
    } else if (arg == "--ggx") {
      ggx = true;
    } else if (arg == "--roughness") {
      if (i + 1 >= argc) return usage_error("--roughness: missing value");
      char* end = nullptr;
      roughness = std::strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0' || !(roughness >= 0.0 && roughness <= 1.0))
        return usage_error(std::string("--roughness: expected a number in 0..1, got '") + argv[i] + "'");
    } else if (arg == "--seed") {
      std::uint64_t value = 0;
      if (i + 1 >= argc) return usage_error("--seed: missing value");
      if (!parse_count(argv[++i], value) || value > 0xffffffffu)
        return usage_error(std::string("--seed: expected an integer in 0..4294967295, got '") + argv[i] + "'");
      seed = std::uint32_t(value);
    } else if (arg == "--rooms") {
      std::uint64_t value = 0;
      if (i + 1 >= argc) return usage_error("--rooms: missing value");
      if (!parse_count(argv[++i], value) || value == 0 || value > kMaxRoomsPerSide)
        return usage_error(std::string("--rooms: expected an integer in 1..") + std::to_string(kMaxRoomsPerSide) +
                           ", got '" + argv[i] + "'");
      rooms = int(value);
    } else if (arg.size() > 1 && arg[0] == '-') {
      return usage_error("unknown option '" + arg + "'");
    } else {
      positional.push_back(arg);
    }
  }
  if (lambert && ggx) return usage_error("--lambert and --ggx exclude each other");
  if (roughness >= 0.0 && !ggx) return usage_error("--roughness needs --ggx");
  if (positional.size() != 2) return usage_error("expected TRIANGLES and OUT, got " + std::to_string(positional.size()) + " arguments");
  std::uint64_t target = 0;
  if (!parse_count(positional[0].c_str(), target) || target == 0 || target > (1ull << 32))
    return usage_error("TRIANGLES: expected a positive integer, got '" + positional[0] + "'");
  const std::string out = positional[1];
  const bool binary = out.size() >= 4 && out.compare(out.size() - 4, 4, ".glb") == 0;
  const bool text = out.size() >= 5 && out.compare(out.size() - 5, 5, ".gltf") == 0;
  if (!binary && !text) return usage_error("OUT must end in .glb or .gltf, got '" + out + "'");

  bp::Scene scene = bp::make_rooms_scene(std::size_t(target), seed, rooms);
  if (lambert)
    for (bp::SceneMaterial& m : scene.materials) m.ks = glm::vec3(0.0f);
  const tinygltf::Model model = to_gltf(scene, ggx, roughness);
  tinygltf::TinyGLTF writer;
  std::ostringstream written;
  bool ok = writer.WriteGltfSceneToStream(&model, written, !binary, binary);
  if (ok) {
    try {
      const std::string bytes = fix_camera(written.str(), binary);
      std::ofstream file(out, std::ios::binary);
      file.write(bytes.data(), std::streamsize(bytes.size()));
      ok = bool(file);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "make_rooms: cannot edit the camera of %s: %s\n", out.c_str(), e.what());
      return 1;
    }
  }
  if (!ok) {
    std::fprintf(stderr, "make_rooms: cannot write %s\n", out.c_str());
    return 1;
  }
  // Read it back through the renderer's loader: same triangles, same emitters, a camera.
  try {
    const bp::Scene back = bp::load_gltf(out);
    if (back.triangles.size() != scene.triangles.size() || !back.camera.from_file ||
        back.emissive_triangles() != scene.emissive_triangles()) {
      std::fprintf(stderr, "make_rooms: %s reads back as %zu triangles (%zu emissive), expected %zu (%zu)\n",
                   out.c_str(), back.triangles.size(), back.emissive_triangles(), scene.triangles.size(),
                   scene.emissive_triangles());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_rooms: %s does not load: %s\n", out.c_str(), e.what());
    return 1;
  }
  const int grid = rooms > 0 ? rooms : bp::rooms_for_triangles(std::size_t(target));
  std::fprintf(stderr, "make_rooms: %s: %zu triangles (%zu emissive), %dx%d rooms, %zu materials%s\n",
               out.c_str(), scene.triangles.size(), scene.emissive_triangles(), grid, grid, scene.materials.size(),
               lambert ? ", all Lambert" : ggx ? ", glTF metallic-roughness (GGX)" : "");
  return 0;
}
