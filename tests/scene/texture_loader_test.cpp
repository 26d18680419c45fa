// glTF textures on the host: images from a file beside the asset, a buffer view, data: URIs (PNG and
// JPEG), decoded to the scene's texel buffer; samplers and texcoords as the views and triangles
// carry them; and the per-patch mean texel RB reflects with (host/scene/textures.h).
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"
#include "scene/patches.h"
#include "scene/textures.h"

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace bp {
namespace {

using test::test_file;

// tests/data/gltf/make_test_files.py's QUAD_TEXELS
std::uint32_t quad_texel(int x, int y) {
  const int a = (x == 3 && y == 0) ? 64 : 255;
  return std::uint32_t(40 + 60 * x) | std::uint32_t(30 + 70 * y) << 8 | std::uint32_t(200 - 40 * x - 10 * y) << 16 |
         std::uint32_t(a) << 24;
}

void expect_quad_texture(const Scene& s, const std::string& what) {
  ASSERT_TRUE(s.has_textures()) << what;
  ASSERT_EQ(s.texture_views.size(), 1u) << what;
  const TextureView& v = s.texture_views[0];
  EXPECT_EQ(v.width, 4u);
  EXPECT_EQ(v.height, 4u);
  EXPECT_EQ(v.flags, BP_WRAP_CLAMP_TO_EDGE | BP_WRAP_CLAMP_TO_EDGE << BP_TEXTURE_WRAP_T_SHIFT | BP_TEXTURE_NEAREST |
                         BP_TEXTURE_SRGB)
      << what;
  ASSERT_EQ(s.texels.size(), 16u) << what;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(s.texels[v.first_texel + 4 * y + x], quad_texel(x, y)) << what << " " << x << "," << y;
  EXPECT_EQ(s.uv_slots, 1u);
  const SceneMaterial& m = s.materials[1];
  EXPECT_EQ(m.textures.base_color, 0u);
  EXPECT_EQ(m.textures.metallic_roughness, BP_NO_TEXTURE);
  // uv = (x, 1 - y) at every corner (glTF's uv origin is the image's top-left)
  ASSERT_EQ(s.triangles.size(), 2u);
  for (const SceneTriangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(t.uv[0][k].x, t.p[k].x, 1e-6f) << what;
      EXPECT_NEAR(t.uv[0][k].y, 1.0f - t.p[k].y, 1e-6f) << what;
    }
}

TEST(GltfTextures, PngBesideTheAssetInABufferViewAndWithUnsignedShortTexcoords) {
  expect_quad_texture(load_gltf(test_file("good/textured-quad.gltf")), "file beside");
  expect_quad_texture(load_gltf(test_file("good/textured-quad-view.gltf")), "buffer view");
  expect_quad_texture(load_gltf(test_file("good/textured-quad-ushort.gltf")), "normalized unsigned short");
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A JPEG (written by stb_image_write) as a data: URI: decoded like a PNG, within JPEG's loss.
TEST(GltfTextures, JpegFromADataUri) {
  std::vector<unsigned char> pixels;
  for (int i = 0; i < 16 * 8; ++i) pixels.insert(pixels.end(), {200, 100, 50});
  std::string jpeg;
  stbi_write_jpg_to_func([](void* out, void* data, int size) { static_cast<std::string*>(out)->append((char*)data, size); },
                         &jpeg, 16, 8, 3, pixels.data(), 95);
  std::string text = read_text(test_file("good/textured-quad.gltf"));
  const std::string uri = "\"uri\": \"textured-quad.png\"";
  const auto at = text.find(uri);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, uri.size(), "\"uri\": \"data:image/jpeg;base64," + test::base64(jpeg) + "\"");
  const Scene s = load_gltf_from_memory(text, "jpeg.gltf", false);
  ASSERT_EQ(s.texture_views.size(), 1u);
  EXPECT_EQ(s.texture_views[0].width, 16u);
  EXPECT_EQ(s.texture_views[0].height, 8u);
  for (std::uint32_t t : s.texels) {
    EXPECT_NEAR(int(t & 255), 200, 3);
    EXPECT_NEAR(int(t >> 8 & 255), 100, 3);
    EXPECT_NEAR(int(t >> 16 & 255), 50, 3);
    EXPECT_EQ(int(t >> 24), 255);
  }
}

// alphaMode MASK keeps its cutoff (default 0.5) with a texture; BLEND is rendered opaque with a warning.
TEST(GltfTextures, AlphaModes) {
  const Scene masked = load_gltf(test_file("good/alpha-mask-quad.gltf"));
  EXPECT_TRUE(masked.has_alpha_masks());
  EXPECT_FLOAT_EQ(masked.materials[1].textures.alpha_cutoff, 0.5f);
  EXPECT_FALSE(load_gltf(test_file("good/textured-quad.gltf")).has_alpha_masks());
  std::string text = read_text(test_file("good/textured-quad-view.gltf"));  // in memory: the image in a buffer view
  const std::string name = "\"name\": \"textured\"";
  const auto at = text.find(name);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + name.size(), ", \"alphaMode\": \"BLEND\"");
  const Scene blend = load_gltf_from_memory(text, "blend.gltf", false);
  EXPECT_FALSE(blend.has_alpha_masks());
  EXPECT_TRUE(test::has_warning(blend, "alphaMode BLEND; rendered opaque"));
}

// KHR_texture_transform on a textureInfo: its offset, rotation and scale as the view's transform, its
// texCoord choosing the set (a primitive without that set reads (0, 0), with a warning).
TEST(GltfTextures, TextureTransformAndItsTexCoord) {
  std::string text = read_text(test_file("good/textured-quad-view.gltf"));
  const std::string info = "\"baseColorTexture\": {";
  const auto at = text.find(info);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + info.size(),
              "\"extensions\": {\"KHR_texture_transform\": {\"offset\": [0.5, 0.25], \"rotation\": 0.3, "
              "\"scale\": [2, 3], \"texCoord\": 1}}, ");
  const Scene s = load_gltf_from_memory(text, "transform.gltf", false);
  ASSERT_EQ(s.texture_views.size(), 1u);
  float expected[6];
  texture_transform(0.5f, 0.25f, 0.3f, 2.0f, 3.0f, expected);
  for (int i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(s.texture_views[0].transform[i], expected[i]) << i;
  EXPECT_TRUE(test::has_warning(s, "lack the TEXCOORD set their material reads"));
  for (const SceneTriangle& t : s.triangles) EXPECT_EQ(t.uv[0][1], glm::vec2(0.0f));
  // a malformed one is exit 3 naming the material
  std::string bad = read_text(test_file("good/textured-quad-view.gltf"));
  bad.insert(bad.find(info) + info.size(), "\"extensions\": {\"KHR_texture_transform\": {\"offset\": 1}}, ");
  EXPECT_THROW(
      {
        try {
          load_gltf_from_memory(bad, "bad-transform.gltf", false);
        } catch (const SceneError& e) {
          EXPECT_NE(std::string(e.what()).find("material 0 \"textured\" baseColorTexture KHR_texture_transform"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      SceneError);
}

// The Khronos sample: one 512 x 512 PNG in a data: URI, used by four materials with their factors.
TEST(GltfTextures, TextureCoordinateTestSampleHasItsTexture) {
  const Scene s = load_gltf(test::gltf_sample("TextureCoordinateTest.gltf"));
  ASSERT_TRUE(s.has_textures());
  ASSERT_EQ(s.texture_views.size(), 4u);
  EXPECT_EQ(s.texels.size(), 512u * 512u);  // decoded once for all four
  for (const TextureView& v : s.texture_views) {
    EXPECT_EQ(v.width, 512u);
    EXPECT_EQ(v.first_texel, 0u);
    EXPECT_EQ(v.flags & BP_TEXTURE_NEAREST, 0u);  // LINEAR magFilter: bilinear
    EXPECT_EQ(v.flags & BP_TEXTURE_WRAP_MASK, BP_WRAP_REPEAT);
  }
  int textured = 0;
  for (const SceneMaterial& m : s.materials) textured += m.textured();
  EXPECT_EQ(textured, 4);
}

// RB's patches reflect with their mean texel: for a texture linear over the patches (bilinear
// between texel centres, away from the clamped edges) the analytic mean over a triangle is the
// value at its centroid.
TEST(GltfTextures, PatchMeanTexelIsTheAnalyticMeanOverThePatch) {
  Scene scene;
  SceneMaterial m;
  m.textures.base_color = 0;
  m.textures.metallic_factor = 0.0f;  // a Lambert glTF material (ggx false): kd = base colour
  scene.materials = {m};
  // an 8 x 1 linear (not sRGB) ramp in red: texel i holds 30 i, so between texel centres
  // red(u) = 30 (8u - 1/2) / 255 exactly
  for (int i = 0; i < 8; ++i) scene.texels.push_back(std::uint32_t(30 * i) | 0xff000000u);
  TextureView v{};
  v.width = 8;
  v.height = 1;
  v.flags = BP_WRAP_CLAMP_TO_EDGE | BP_WRAP_CLAMP_TO_EDGE << BP_TEXTURE_WRAP_T_SHIFT;
  texture_transform(0, 0, 0, 1, 1, v.transform);
  scene.texture_views = {v};
  scene.uv_slots = 1;
  // a 1 m quad whose u runs over [1/16, 15/16] (texel centres 0 to 7) along x
  const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  auto u_of = [](const glm::vec3& q) { return 1.0f / 16.0f + q.x * 14.0f / 16.0f; };
  for (auto [a, b, c] : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
    SceneTriangle t{{p[a], p[b], p[c]}, 0};
    const int corners[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) t.uv[0][k] = glm::vec2(u_of(p[corners[k]]), 0.5f);
    scene.triangles.push_back(t);
  }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& q : t.p) scene.bounds.grow(q);
  const PatchLayout patches = build_patch_layout(scene, 0.3f);
  std::vector<Material> materials(1);
  const std::vector<Material> means = patch_mean_materials(scene, patches, materials);
  ASSERT_EQ(means.size(), patches.patch_count);
  ASSERT_GT(patches.patch_count, 8u);
  for_each_sub_triangle(scene, patches, [&](const SubTriangle& sub) {
    glm::vec3 centroid(0.0f);
    for (int k = 0; k < 3; ++k) centroid += scene.triangles[sub.triangle].p[0] + sub.b1[k] * sub.e1 + sub.b2[k] * sub.e2;
    centroid /= 3.0f;
    const float expected = 30.0f * (8.0f * u_of(centroid) - 0.5f) / 255.0f;
    const std::uint32_t patch = patches.first_patch[sub.triangle] + sub.local;
    EXPECT_NEAR(means[patch].kd[0], expected, 2e-5f) << "patch " << patch;
    EXPECT_EQ(means[patch].kd[1], 0.0f);
    EXPECT_EQ(means[patch].ks[0], 0.0f);
  });
}

}  // namespace
}  // namespace bp
