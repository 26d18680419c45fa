// Writes the procedural rooms scene (bp::make_rooms_scene, host/scene/procedural.h) as a glTF
// binary (.glb) or .gltf, so `bundlepath render` can draw it: materials as extras.phong plus
// emissiveFactor / KHR_materials_emissive_strength, double-sided walls as doubleSided, the camera as
// a node. The file is read back with the renderer's own loader and checked (triangle count,
// materials, camera) before the tool reports success.
// Usage: make_rooms TRIANGLES OUT.glb|OUT.gltf [--seed N]
#include "scene/tinygltf.h"

#include "scene/gltf_loader.h"
#include "scene/procedural.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

tinygltf::Value rgb_value(const glm::vec3& c) {
  return tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(c.x)), tinygltf::Value(double(c.y)),
                                                 tinygltf::Value(double(c.z))});
}

tinygltf::Model to_gltf(const bp::Scene& scene) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "bundlepath bench/make_rooms (" + scene.source + ")";
  bool emissive_strength = false;
  for (const bp::SceneMaterial& m : scene.materials) {
    tinygltf::Material out;
    out.name = m.name;
    out.doubleSided = m.double_sided;
    tinygltf::Value::Object phong;
    phong["kd"] = rgb_value(m.kd);
    phong["ks"] = rgb_value(m.ks);
    phong["shininess"] = tinygltf::Value(double(m.shininess));
    out.extras = tinygltf::Value(tinygltf::Value::Object{{"phong", tinygltf::Value(phong)}});
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_rooms TRIANGLES OUT.glb|OUT.gltf [--seed N]\n");
    return 2;
  }
  const std::size_t target = std::stoull(argv[1]);
  const std::string out = argv[2];
  std::uint32_t seed = 1;
  for (int i = 3; i < argc; ++i)
    if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc) seed = std::uint32_t(std::stoul(argv[++i]));
  const bp::Scene scene = bp::make_rooms_scene(target, seed);
  const tinygltf::Model model = to_gltf(scene);
  const bool binary = out.size() >= 4 && out.compare(out.size() - 4, 4, ".glb") == 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, out, false, true, !binary, binary)) {
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
  std::fprintf(stderr, "make_rooms: %s: %zu triangles (%zu emissive), %zu materials\n", out.c_str(),
               scene.triangles.size(), scene.emissive_triangles(), scene.materials.size());
  return 0;
}
