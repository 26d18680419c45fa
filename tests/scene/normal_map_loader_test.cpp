// glTF normal maps on the host (docs/design.md §6): normalTexture (linear, its scale and texCoord), TANGENT
// read, placed by the node (mirrored too) and checked, and tangents generated where it is missing.
// The files are written here: a unit quad in z = 0 facing +z, with a 2 x 2 normal map as a data: URI;
// the same quad carries the KHR_materials_specular texture test.
#include "device/kernel_features.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace bp {
namespace {

using nlohmann::json;

struct QuadFile {
  bool normals = true;
  std::vector<float> tangents;  // 4 x VEC4, or none
  bool mirrored_uv = false;     // u = 1 - x instead of x
  bool degenerate_uv = false;   // every corner at uv (0.5, 0.5)
  json node = json::object();   // the mesh's node (transform)
  json normal_texture = {{"index", 0}, {"scale", 0.5}};
  std::string tangent_type = "VEC4";
  int tangent_count = 4;
  json specular = {{"specularFactor", 0.0}};  // the material's KHR_materials_specular
};

std::string png_2x2() {
  const unsigned char texels[] = {128, 128, 255, 200, 128, 230, 128, 60, 230, 255, 255, 255};
  std::string png;
  stbi_write_png_to_func([](void* out, void* data, int size) { static_cast<std::string*>(out)->append((char*)data, size); },
                         &png, 2, 2, 3, texels, 6);
  return png;
}

// The glTF text of the quad: POSITION, NORMAL, TEXCOORD_0 (x, 1 - y: the image upright), TEXCOORD_1
// (twice TEXCOORD_0), TANGENT, indices 0 1 2, 0 2 3, in one data: buffer.
std::string quad_gltf(const QuadFile& q) {
  std::string bin;
  auto put = [&](const std::vector<float>& v) {
    const std::size_t at = bin.size();
    bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
    return at;
  };
  const float xs[4] = {0, 1, 1, 0}, ys[4] = {0, 0, 1, 1};
  std::vector<float> pos, nor, uv0, uv1;
  for (int i = 0; i < 4; ++i) {
    pos.insert(pos.end(), {xs[i], ys[i], 0.0f});
    nor.insert(nor.end(), {0.0f, 0.0f, 1.0f});
    float u = q.mirrored_uv ? 1.0f - xs[i] : xs[i], v = 1.0f - ys[i];
    if (q.degenerate_uv) u = v = 0.5f;
    uv0.insert(uv0.end(), {u, v});
    uv1.insert(uv1.end(), {2 * u, 2 * v});
  }
  json views = json::array(), accessors = json::array();
  auto add = [&](std::size_t offset, std::size_t bytes, int count, const std::string& type, int component) {
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}});
    return int(accessors.size() - 1);
  };
  json attributes;
  attributes["POSITION"] = add(put(pos), 48, 4, "VEC3", 5126);
  accessors.back()["min"] = {0, 0, 0};
  accessors.back()["max"] = {1, 1, 0};
  if (q.normals) attributes["NORMAL"] = add(put(nor), 48, 4, "VEC3", 5126);
  attributes["TEXCOORD_0"] = add(put(uv0), 32, 4, "VEC2", 5126);
  attributes["TEXCOORD_1"] = add(put(uv1), 32, 4, "VEC2", 5126);
  if (!q.tangents.empty())
    attributes["TANGENT"] = add(put(q.tangents), q.tangents.size() * 4, q.tangent_count, q.tangent_type, 5126);
  const std::uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  const std::size_t idx_at = bin.size();
  bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
  const int indices = add(idx_at, sizeof idx, 6, "SCALAR", 5123);
  json node = q.node;
  node["mesh"] = 0;
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {node}},
      {"meshes", {{{"primitives", {{{"attributes", attributes}, {"indices", indices}, {"material", 0}}}}}}},
      {"materials",
       {{{"name", "bumpy"},
         {"normalTexture", q.normal_texture},
         {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
         {"extensions", {{"KHR_materials_specular", q.specular}}}}}},
      {"textures", {{{"source", 0}}}},
      {"images", {{{"uri", "data:image/png;base64," + test::base64(png_2x2())}}}},
      {"buffers", {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + test::base64(bin)}}}},
      {"bufferViews", views},
      {"accessors", accessors},
  };
  return doc.dump();
}

Scene load_quad(const QuadFile& q) { return load_gltf_from_memory(quad_gltf(q), "quad.gltf", false); }

std::vector<float> tangents_all(float x, float y, float z, float w) {
  std::vector<float> t;
  for (int i = 0; i < 4; ++i) t.insert(t.end(), {x, y, z, w});
  return t;
}

void expect_tangents(const Scene& s, glm::vec4 expected, const std::string& what) {
  ASSERT_EQ(s.triangles.size(), 2u) << what;
  for (const SceneTriangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(t.tangent[k][c], expected[c], 1e-5f) << what << ": corner " << k << " component " << c;
      EXPECT_NEAR(glm::dot(glm::vec3(t.tangent[k]), t.normal[k]), 0.0f, 1e-5f) << what << ": orthogonal to the normal";
    }
}

// KHR_materials_specular's textures (the quad's PNG): specularTexture a linear view (its alpha),
// specularColorTexture an sRGB one, each with its texCoord and KHR_texture_transform; the factors
// they multiply kept beside them (texel_material), f0 before the cap at 1; no warning.
TEST(GltfSpecularTextures, AreViewsWithTheFactorsTheyMultiply) {
  QuadFile q;
  q.specular = {{"specularFactor", 0.7},
                {"specularColorFactor", {30.0, 1.0, 0.5}},
                {"specularTexture", {{"index", 0}, {"texCoord", 1}}},
                {"specularColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"rotation", 0.5}}}}}}}};
  const Scene s = load_quad(q);
  const SceneMaterial& m = s.materials[1];
  EXPECT_TRUE(m.textured()) << "specular textures make f textured";
  EXPECT_TRUE(m.ggx);
  ASSERT_NE(m.textures.specular, BP_NO_TEXTURE);
  ASSERT_NE(m.textures.specular_color, BP_NO_TEXTURE);
  const TextureView& spec = s.texture_views[m.textures.specular];
  const TextureView& colour = s.texture_views[m.textures.specular_color];
  EXPECT_EQ(spec.flags & BP_TEXTURE_SRGB, 0u) << "specularTexture is linear";
  EXPECT_NE(colour.flags & BP_TEXTURE_SRGB, 0u) << "specularColorTexture is sRGB";
  EXPECT_NEAR(s.triangles[0].uv[spec.uv_slot][1].x, 2.0f, 1e-6f) << "texCoord 1 reads TEXCOORD_1";
  EXPECT_NEAR(colour.transform[1], std::sin(0.5f), 1e-6f) << "KHR_texture_transform read";
  EXPECT_FLOAT_EQ(m.textures.specular_factor, 0.7f);
  EXPECT_NEAR(m.textures.specular_f0[0], 0.04f * 30.0f, 1e-6f) << "f0 before the cap (the texel may lower it)";
  EXPECT_NEAR(m.textures.specular_f0[2], 0.02f, 1e-6f);
  EXPECT_FLOAT_EQ(m.dielectric_f0.x, 1.0f) << "the untextured f0 is capped";
  for (const std::string& w : s.warnings) EXPECT_EQ(w.find("specular"), std::string::npos) << w;

  q.specular["specularTexture"] = {{"index", "zero"}};
  try {
    load_quad(q);
    ADD_FAILURE() << "a malformed specularTexture loaded";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("KHR_materials_specular.specularTexture is malformed"), std::string::npos)
        << e.what();
  }
}

TEST(GltfNormalMaps, NormalTextureIsALinearViewWithItsScaleAndTexCoord) {
  QuadFile q;
  q.tangents = tangents_all(1, 0, 0, 1);
  const Scene s = load_quad(q);
  const SceneMaterial& m = s.materials[1];
  ASSERT_TRUE(m.has_normal_map());
  EXPECT_FALSE(m.textured()) << "a normal map alone leaves f and the emission untextured";
  EXPECT_TRUE(s.has_normal_maps() && s.has_textures() && s.has_shading_normals());
  EXPECT_TRUE(features_for(s, true).normal_maps);
  EXPECT_FLOAT_EQ(m.textures.normal_scale, 0.5f);
  const TextureView& v = s.texture_views[m.textures.normal];
  EXPECT_EQ(v.flags & BP_TEXTURE_SRGB, 0u) << "normal maps are linear";
  EXPECT_EQ(v.width, 2u);
  EXPECT_EQ(v.uv_slot, 0u);
  EXPECT_NEAR(s.triangles[0].uv[0][1].x, 1.0f, 1e-6f);  // corner 1 of the quad: TEXCOORD_0 (1, 1)
  expect_tangents(s, {1, 0, 0, 1}, "given TANGENT");
  // texCoord 1 reads TEXCOORD_1
  q.normal_texture["texCoord"] = 1;
  const Scene s1 = load_quad(q);
  EXPECT_NEAR(s1.triangles[0].uv[s1.texture_views[0].uv_slot][1].x, 2.0f, 1e-6f);
  // a scene without normal maps builds without them
  EXPECT_FALSE(features_for(load_gltf(test::test_file("good/textured-quad.gltf")), true).normal_maps);
}

TEST(GltfNormalMaps, TangentsFollowTheNodeAndAMirrorReversesTheirHandedness) {
  QuadFile q;
  q.tangents = tangents_all(1, 0, 0, 1);
  q.node = {{"rotation", {0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)}}};  // 90 degrees about z: x -> y
  expect_tangents(load_quad(q), {0, 1, 0, 1}, "rotated");
  q.node = {{"scale", {-1.0, 1.0, 1.0}}};  // a mirror: the tangent moves with it, the handedness flips
  const Scene mirrored = load_quad(q);
  expect_tangents(mirrored, {-1, 0, 0, -1}, "mirrored");
  // the mirrored frame's bitangent w cross(N, T) is the mirror of the original one, cross(z, x) = +y
  const SceneTriangle& t = mirrored.triangles[0];
  const glm::vec3 b = t.tangent[0].w * glm::cross(t.normal[0], glm::vec3(t.tangent[0]));
  EXPECT_NEAR(b.y, 1.0f, 1e-5f);
  // a shear: the moved tangent is made orthogonal to the normal again (expect_tangents checks it)
  q.tangents = tangents_all(std::sqrt(0.5f), 0, std::sqrt(0.5f), 1);  // not orthogonal to +z: re-orthogonalised
  q.node = {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1}}};
  expect_tangents(load_quad(q), {1, 0, 0, 1}, "sheared");
}

TEST(GltfNormalMaps, MissingTangentsAreGeneratedWithTheHandednessOfTheUvs) {
  QuadFile q;
  expect_tangents(load_quad(q), {1, 0, 0, 1}, "generated");
  q.mirrored_uv = true;  // u runs along -x: T = -x, and B (up the image, +y) = w cross(+z, -x) needs w = -1
  expect_tangents(load_quad(q), {-1, 0, 0, -1}, "generated, mirrored uv");
  q.mirrored_uv = false;
  q.normals = false;  // no NORMAL: flat normals (glTF), the tangents still generated
  const Scene flat = load_quad(q);
  expect_tangents(flat, {1, 0, 0, 1}, "no NORMAL");
  for (const SceneTriangle& t : flat.triangles) EXPECT_TRUE(t.has_normals);
  q.tangents = tangents_all(0, 1, 0, 1);  // ignored without NORMAL, as glTF says, with a warning
  const Scene ignored = load_quad(q);
  expect_tangents(ignored, {1, 0, 0, 1}, "TANGENT without NORMAL");
  EXPECT_TRUE(test::has_warning(ignored, "TANGENT but no NORMAL"));
}

TEST(GltfNormalMaps, DegenerateUvsFallBackToAnyTangentWithOneWarning) {
  QuadFile q;
  q.degenerate_uv = true;
  const Scene s = load_quad(q);
  for (const SceneTriangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(glm::length(glm::vec3(t.tangent[k])), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(glm::vec3(t.tangent[k]), t.normal[k]), 0.0f, 1e-5f);
    }
  int warnings = 0;
  for (const std::string& w : s.warnings) warnings += w.find("no direction from their texcoords") != std::string::npos;
  EXPECT_EQ(warnings, 1);
  EXPECT_TRUE(test::has_warning(s, "4 normal-mapped vertex tangent(s)")) << "one per shared vertex";
}

void expect_error(const QuadFile& q, const std::string& part) {
  try {
    load_quad(q);
    ADD_FAILURE() << "loaded; expected an error containing \"" << part << "\"";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(GltfNormalMaps, BadTangentsAreClearErrors) {
  QuadFile q;
  q.tangents = tangents_all(1, 0, 0, 1);
  q.tangent_count = 3;
  expect_error(q, "(TANGENT of mesh 0 primitive 0) has 3 elements, but POSITION has 4");
  q = QuadFile{};
  q.tangents = tangents_all(1, 0, 0, 1);
  q.tangents[5] = std::numeric_limits<float>::quiet_NaN();
  expect_error(q, "(TANGENT of mesh 0 primitive 0) holds a non-finite tangent at element 1");
  q = QuadFile{};
  q.tangents = std::vector<float>(12, 0.0f);
  q.tangent_type = "VEC3";
  expect_error(q, "(TANGENT of mesh 0 primitive 0) has type VEC3; expected VEC4");
  q = QuadFile{};
  q.normal_texture = {{"index", 3}};
  expect_error(q, "material 0 \"bumpy\" normalTexture refers to texture 3, but the file has 1 textures");
}

}  // namespace
}  // namespace bp
