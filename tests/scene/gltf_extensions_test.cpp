// No silent drops (scene/gltf_extensions.h): a required extension we cannot do is an error naming
// it; an unsupported used one, one warning per name with its count; core features the loader
// ignores, one warning each. The files are written here: one emissive triangle, grown per test.
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

namespace bp {
namespace {

using nlohmann::json;
using test::has_warning;

json data_buffer(const std::string& bin) {
  return {{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + test::base64(bin)}};
}

// A triangle (0,0,0) (1,0,0) (0,1,0) in one data: buffer, with `materials` emissive materials.
json triangle_doc(int materials = 1) {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string bin(reinterpret_cast<const char*>(pos), sizeof pos);
  json doc;
  doc["asset"] = {{"version", "2.0"}};
  doc["buffers"] = json::array({data_buffer(bin)});
  doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", bin.size()}}});
  doc["accessors"] = json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}}});
  doc["materials"] = json::array();
  for (int i = 0; i < materials; ++i)
    doc["materials"].push_back({{"name", "m" + std::to_string(i)}, {"emissiveFactor", {1, 1, 1}}});
  doc["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"material", 0}}})}}});
  doc["nodes"] = json::array({{{"mesh", 0}}});
  doc["scenes"] = json::array({{{"nodes", {0}}}});
  doc["scene"] = 0;
  return doc;
}

Scene load(const json& doc) { return load_gltf_from_memory(doc.dump(), "mem.gltf", false); }

std::string load_error(const json& doc) {
  try {
    load(doc);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

int warnings_naming(const Scene& s, const std::string& part) {
  int n = 0;
  for (const auto& w : s.warnings) n += w.find(part) != std::string::npos;
  return n;
}

void use(json& doc, const std::string& name, bool required) {
  doc["extensionsUsed"].push_back(name);
  if (required) doc["extensionsRequired"].push_back(name);
}

TEST(GltfExtensions, RequiredUnsupportedIsAnErrorNamingItAndWhatIsSupported) {
  json doc = triangle_doc();
  use(doc, "KHR_materials_clearcoat", true);
  doc["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0}};
  const std::string error = load_error(doc);
  EXPECT_NE(error.find("mem.gltf: requires KHR_materials_clearcoat (extensionsRequired)"), std::string::npos) << error;
  EXPECT_NE(error.find("KHR_texture_transform"), std::string::npos) << "names what is supported: " << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << "one line";
}

TEST(GltfExtensions, RequiredSupportedLoads) {
  json doc = triangle_doc();
  use(doc, "KHR_materials_emissive_strength", true);
  doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", 4.0}};
  const Scene s = load(doc);
  EXPECT_FLOAT_EQ(s.materials[1].emission.x, 4.0f);
  EXPECT_FALSE(has_warning(s, "not supported"));
}

TEST(GltfExtensions, UsedUnsupportedWarnsOncePerNameWithItsCount) {
  json doc = triangle_doc(3);
  use(doc, "KHR_materials_clearcoat", false);
  for (auto& m : doc["materials"]) m["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0}};
  const Scene s = load(doc);
  EXPECT_EQ(warnings_naming(s, "KHR_materials_clearcoat"), 1);
  EXPECT_TRUE(has_warning(s, "KHR_materials_clearcoat (used by 3 materials) is not supported; the clearcoat layer is left out"));
}

TEST(GltfExtensions, ImplementedExtensionsDoNotWarn) {
  json doc = triangle_doc();
  for (const char* name : {"KHR_materials_ior", "KHR_materials_specular", "KHR_materials_emissive_strength"})
    use(doc, name, false);
  doc["materials"][0]["extensions"] = {{"KHR_materials_ior", {{"ior", 1.4}}},
                                       {"KHR_materials_specular", {{"specularFactor", 0.5}}},
                                       {"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}};
  const Scene s = load(doc);
  EXPECT_FALSE(has_warning(s, "KHR_")) << s.warnings.front();
}

TEST(GltfExtensions, UnknownExtensionGetsTheGenericWarning) {
  json doc = triangle_doc();
  doc["nodes"][0]["extensions"]["EXT_made_up"] = json::object();
  use(doc, "VENDOR_listed_only", false);
  doc["materials"][0]["extras"]["extensions"]["EXT_in_extras"] = json::object();  // the application's, not glTF's
  const Scene s = load(doc);
  EXPECT_TRUE(has_warning(s, "EXT_made_up (used by 1 node) is not supported; it is ignored"));
  EXPECT_TRUE(has_warning(s, "VENDOR_listed_only (listed in extensionsUsed) is not supported"));
  EXPECT_FALSE(has_warning(s, "EXT_in_extras"));
}

TEST(GltfExtensions, InstancingIsWarnedAsDropped) {
  json doc = triangle_doc();
  use(doc, "EXT_mesh_gpu_instancing", false);
  doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = {{"attributes", {{"TRANSLATION", 0}}}};
  const Scene s = load(doc);
  EXPECT_TRUE(has_warning(s, "EXT_mesh_gpu_instancing (used by 1 node) is not supported; each node draws its mesh once"));
  EXPECT_EQ(s.triangles.size(), 1u);
}

TEST(GltfExtensions, DracoWithFallbackWarnsRequiredOrWithoutFallbackFails) {
  json doc = triangle_doc();
  use(doc, "KHR_draco_mesh_compression", false);
  doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {{"bufferView", 0},
                                                                                    {"attributes", {{"POSITION", 0}}}};
  EXPECT_TRUE(has_warning(load(doc), "KHR_draco_mesh_compression (used by 1 mesh) is not supported; the primitives' "
                                     "uncompressed fallback attributes are read"));
  json no_fallback = doc;
  no_fallback["accessors"][0].erase("bufferView");
  EXPECT_NE(load_error(no_fallback).find("mesh 0 primitive 0 is Draco-compressed"), std::string::npos)
      << load_error(no_fallback);
  use(doc, "KHR_draco_mesh_compression", true);
  EXPECT_NE(load_error(doc).find("requires KHR_draco_mesh_compression"), std::string::npos);
}

TEST(GltfExtensions, OcclusionTextureWarnedOncePerScene) {
  json doc = triangle_doc(2);
  doc["textures"] = json::array({json::object()});
  for (auto& m : doc["materials"]) m["occlusionTexture"] = {{"index", 0}};
  const Scene s = load(doc);
  EXPECT_EQ(warnings_naming(s, "occlusionTexture"), 1);
  EXPECT_TRUE(has_warning(s, "occlusionTexture ignored: occlusion is computed by the renderer (2 material(s))"));
}

// KHR_mesh_quantization: POSITION as normalized shorts (32767 -> 1), read only where the file uses it.
TEST(GltfExtensions, QuantizedPositionsAreRead) {
  json doc = triangle_doc();
  const std::int16_t pos[12] = {0, 0, 0, 0, 32767, 0, 0, 0, 0, 32767, 0, 0};  // 8-byte aligned VEC3 elements
  const std::string bin(reinterpret_cast<const char*>(pos), sizeof pos);
  doc["buffers"][0] = data_buffer(bin);
  doc["bufferViews"][0] = {{"buffer", 0}, {"byteLength", bin.size()}, {"byteStride", 8}};
  doc["accessors"][0].update({{"componentType", 5122}, {"normalized", true}});
  EXPECT_NE(load_error(doc).find("unsupported component type"), std::string::npos) << "core glTF: float positions";
  use(doc, "KHR_mesh_quantization", true);
  const Scene s = load(doc);
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_FLOAT_EQ(s.triangles[0].p[1].x, 1.0f);
  EXPECT_FLOAT_EQ(s.triangles[0].p[2].y, 1.0f);
  EXPECT_FALSE(has_warning(s, "KHR_mesh_quantization"));
}

}  // namespace
}  // namespace bp
