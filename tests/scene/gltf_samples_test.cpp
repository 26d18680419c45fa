// The Khronos sample files (tests/data/gltf/samples, see its README): every one must load.
// Expected counts and bounds are read off the JSON by hand (index count / 3, node transforms).
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <vector>

namespace bp {
namespace {

using test::gltf_sample;
using test::has_warning;

struct SampleCase {
  const char* file;
  std::size_t triangles;
  glm::vec3 lo, hi;
};

class GltfSample : public ::testing::TestWithParam<SampleCase> {};

TEST_P(GltfSample, LoadsWithExpectedTrianglesAndBounds) {
  const SampleCase& c = GetParam();
  const Scene s = load_gltf(gltf_sample(c.file));
  EXPECT_EQ(s.triangles.size(), c.triangles);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.bounds.lo[i], c.lo[i], 1e-4) << "axis " << i;
    EXPECT_NEAR(s.bounds.hi[i], c.hi[i], 1e-4) << "axis " << i;
  }
  EXPECT_TRUE(has_warning(s, "no emitter")) << "no sample has an emissive material";
  for (const auto& t : s.triangles) EXPECT_LT(t.material, s.materials.size());
}

INSTANTIATE_TEST_SUITE_P(
    All, GltfSample,
    ::testing::Values(
        SampleCase{"Triangle.gltf", 1, {0, 0, 0}, {1, 1, 0}},
        SampleCase{"TriangleWithoutIndices.gltf", 1, {0, 0, 0}, {1, 1, 0}},
        SampleCase{"AnimatedTriangle.gltf", 1, {0, 0, 0}, {1, 1, 0}},
        SampleCase{"SimpleMorph.gltf", 1, {0, 0, 0}, {1, 0.5f, 0}},         // base positions, no morph
        SampleCase{"SimpleMeshes.gltf", 2, {0, 0, 0}, {2, 1, 0}},           // second node at x + 1
        SampleCase{"Box.gltf", 12, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}},
        SampleCase{"BoxVertexColors.gltf", 12, {0, 0, 0}, {1, 1, 1}},
        SampleCase{"Cameras.gltf", 2, {0, 0, -0.70759f}, {1, 0.706623f, 0}},
        SampleCase{"MeshPrimitiveModes.gltf", 16, {-2.866f, -4, 0}, {2.866f, -2, 0}},  // 6 + 4 + 6
        SampleCase{"MultipleScenes.gltf", 2, {0, 0, 0}, {1, 1, 0}},          // scene 1: the quad
        SampleCase{"OrientationTest.gltf", 524, {-5.33065f, -5.33065f, -5.33065f}, {5.33065f, 5.33065f, 5.33065f}},
        SampleCase{"SimpleSkin.gltf", 8, {-0.5f, 0, 0}, {0.5f, 2, 0}},
        SampleCase{"SimpleSparseAccessor.gltf", 12, {0, 0, 0}, {6, 4, 0}},  // y = 4 only after the sparse part
        SampleCase{"TextureCoordinateTest.gltf", 10, {-1.2f, -1.2f, 0}, {1.2f, 1.2f, 0.052591f}}),
    [](const auto& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find('.'));
    });

TEST(GltfSamples, PrimitiveModesAreTriangulatedFrontFacingAndOthersWarned) {
  const Scene s = load_gltf(gltf_sample("MeshPrimitiveModes.gltf"));
  for (const char* mode : {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"}) {
    int count = 0;
    for (const auto& w : s.warnings)
      if (w.find(std::string("mode ") + mode + ";") != std::string::npos) ++count;
    EXPECT_EQ(count, 1) << mode;
  }
  EXPECT_FALSE(test::has_warning(s, "mode TRIANGLE"));
  // Every strip and fan triangle faces +z like the TRIANGLES mesh: the strip winding is kept.
  for (const auto& t : s.triangles) EXPECT_GT(test::normal_of(t).z, 0.0f);
}

TEST(GltfSamples, BoxMaterialIsCoreMetallicRoughness) {
  const Scene s = load_gltf(gltf_sample("Box.gltf"));
  ASSERT_EQ(s.materials.size(), 2u);  // default + the file's one
  const SceneMaterial& m = s.materials[1];
  // baseColor (0.8, 0, 0), metallic 1 and roughness 1 by default: a rough red conductor, F0 = baseColor.
  EXPECT_TRUE(m.ggx);
  EXPECT_NEAR(m.base_color.x, 0.8f, 1e-6);
  EXPECT_NEAR(m.base_color.y, 0.0f, 1e-6);
  EXPECT_NEAR(m.metallic, 1.0f, 1e-6);
  EXPECT_NEAR(m.roughness, 1.0f, 1e-6);
  for (const auto& t : s.triangles) EXPECT_EQ(t.material, 1u);
}

TEST(GltfSamples, PerspectiveCameraFromNodeAndOrthographicIgnored) {
  const Scene s = load_gltf(gltf_sample("Cameras.gltf"));
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_NEAR(s.camera.position.x, 0.5f, 1e-6);
  EXPECT_NEAR(s.camera.position.y, 0.5f, 1e-6);
  EXPECT_NEAR(s.camera.position.z, 3.0f, 1e-6);
  EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-6);
  EXPECT_NEAR(s.camera.up.y, 1.0f, 1e-6);
  EXPECT_NEAR(s.camera.yfov, 0.7f, 1e-6);
  EXPECT_NEAR(s.camera.aspect, 1.0f, 1e-6);
  EXPECT_TRUE(has_warning(s, "orthographic"));
  EXPECT_FALSE(has_warning(s, "no camera"));
}

TEST(GltfSamples, DefaultViewWhenNoCamera) {
  const Scene s = load_gltf(gltf_sample("Box.gltf"));
  EXPECT_FALSE(s.camera.from_file);
  EXPECT_TRUE(has_warning(s, "no camera in file; using a default view"));
  EXPECT_NEAR(s.camera.position.x, 0.0f, 1e-6);
  EXPECT_NEAR(s.camera.position.y, 0.0f, 1e-6);
  // Bounding sphere radius sqrt(3)/2 fits half the vertical field of view.
  EXPECT_NEAR(s.camera.position.z, 0.5f * std::sqrt(3.0f) / std::sin(0.5f * s.camera.yfov), 1e-4);
  EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-6);
}

TEST(GltfSamples, InstancedMeshAppearsPerNode) {
  const Scene s = load_gltf(gltf_sample("SimpleMeshes.gltf"));
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_NEAR(s.triangles[1].p[0].x - s.triangles[0].p[0].x, 1.0f, 1e-6);
}

// Every sample in the folder loads, and its warnings are exactly what it uses and the render leaves
// out (scene/gltf_extensions.h), each once -- besides the lack of a camera or an emitter.
TEST(GltfSamples, EveryFileLoadsWarningOnlyOfWhatIsLeftOut) {
  const std::map<std::string, std::vector<std::string>> left_out = {
      {"AnimatedTriangle.gltf", {"animations ignored"}},
      {"BoxVertexColors.gltf", {"COLOR_0 vertex colours ignored"}},
      {"Cameras.gltf", {"is orthographic; ignored"}},
      {"MeshPrimitiveModes.gltf", {"mode POINTS;", "mode LINES;", "mode LINE_LOOP;", "mode LINE_STRIP;"}},
      {"SimpleMorph.gltf", {"morph targets ignored", "animations ignored"}},
      {"SimpleSkin.gltf", {"skins ignored", "animations ignored"}},
  };
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(gltf_sample(""))) {
    if (entry.path().extension() != ".gltf") continue;
    ++files;
    const std::string file = entry.path().filename().string();
    const Scene s = load_gltf(entry.path().string());
    std::vector<std::string> expected = {"no emitter", "no camera in file"};
    if (auto it = left_out.find(file); it != left_out.end()) expected.insert(expected.end(), it->second.begin(), it->second.end());
    for (const auto& w : s.warnings) {
      int matches = 0;
      for (const auto& e : expected) matches += w.find(e) != std::string::npos;
      EXPECT_EQ(matches, 1) << file << ": unexpected warning \"" << w << "\"";
    }
    for (std::size_t e = 2; e < expected.size(); ++e)
      EXPECT_TRUE(has_warning(s, expected[e])) << file << ": no warning \"" << expected[e] << "\"";
  }
  EXPECT_EQ(files, 14);
}

}  // namespace
}  // namespace bp
