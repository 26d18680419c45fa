// Patch sub-triangle indexing (kernels/shared/patch.h) and the per-triangle patch layout.
#include "kernels/shared/patch.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"
#include "scene/patches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace bp {
namespace {

TEST(PatchIndexing, CentroidOfEverySubTriangleMapsBackToItsIndex) {
  for (bp_u32 k = 1; k <= 12; ++k) {
    for (bp_u32 local = 0; local < k * k; ++local) {
      float b1[3], b2[3];
      patch_corner_barycentrics(local, k, b1, b2);
      const float c1 = (b1[0] + b1[1] + b1[2]) / 3.0f, c2 = (b2[0] + b2[1] + b2[2]) / 3.0f;
      EXPECT_EQ(patch_local_index(c1, c2, k), local) << "k " << k;
    }
  }
}

TEST(PatchIndexing, SubTrianglesAreCounterClockwiseWithEqualAreas) {
  for (bp_u32 k = 1; k <= 12; ++k) {
    double total = 0.0;
    for (bp_u32 local = 0; local < k * k; ++local) {
      float b1[3], b2[3];
      patch_corner_barycentrics(local, k, b1, b2);
      // Area in barycentric (b1, b2) space, relative to the parent's 1/2; positive = same winding.
      const double det = double(b1[1] - b1[0]) * (b2[2] - b2[0]) - double(b1[2] - b1[0]) * (b2[1] - b2[0]);
      EXPECT_NEAR(det, 1.0 / (double(k) * k), 1e-6) << "k " << k << " local " << local;
      total += det;
    }
    EXPECT_NEAR(total, 1.0, 1e-5);
  }
}

TEST(PatchIndexing, CornersAndEdgesStayInRange) {
  for (bp_u32 k = 1; k <= 12; ++k)
    for (float b1 : {0.0f, 0.5f, 1.0f})
      for (float b2 : {0.0f, 0.5f, 1.0f})
        if (b1 + b2 <= 1.0f) {
          EXPECT_LT(patch_local_index(b1, b2, k), k * k);
        }
}

Scene two_triangle_scene() {
  Scene s;
  s.materials.resize(2);
  s.materials[1].double_sided = true;
  s.triangles.push_back({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 0});      // longest edge sqrt(2)
  s.triangles.push_back({{{0, 0, 0}, {1, 0, 0}, {0.5f, 0.5f, 0}}, 1});  // longest 1, double-sided
  s.triangles.push_back({{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, 0});      // degenerate: k = 1
  for (const auto& t : s.triangles)
    for (const auto& p : t.p) s.bounds.grow(p);
  return s;
}

TEST(PatchLayout, CountsForAKnownScene) {
  const PatchLayout l = build_patch_layout(two_triangle_scene(), 0.5f);
  EXPECT_EQ(l.target_size, 0.5f);
  ASSERT_EQ(l.subdiv.size(), 3u);
  EXPECT_EQ(l.subdiv[0], 3u);  // ceil(1.414 / 0.5)
  EXPECT_EQ(l.subdiv[1], 2u);
  EXPECT_EQ(l.subdiv[2], 1u);
  EXPECT_EQ(l.first_patch[0], 0u);
  EXPECT_EQ(l.first_patch[1], 9u);
  EXPECT_EQ(l.first_patch[2], 9u + 2u * 4u);  // front then back patches
  EXPECT_EQ(l.patch_count, 18u);
}

TEST(PatchLayout, RejectsBadTargetsNamingTheOption) {
  const Scene s = two_triangle_scene();
  for (float bad : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    1e-7f /* ~2e14 patches */}) {
    try {
      build_patch_layout(s, bad);
      FAIL() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--patch-size"), std::string::npos) << e.what();
    }
  }
}

TEST(PatchLayout, DefaultSizeGivesTheCornellBoxAFewThousandPatches) {
  const Scene s = load_gltf(test::scene_file("cornell-box.gltf"));
  const float size = default_patch_size(s);
  EXPECT_NEAR(size, glm::length(s.bounds.extent()) / 20.0f, 1e-6);
  const PatchLayout l = build_patch_layout(s, size);
  EXPECT_EQ(l.patch_count, 3734u);
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& t = s.triangles[i];
    const float longest = std::max({glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]),
                                    glm::length(t.p[0] - t.p[2])});
    EXPECT_LE(longest / float(l.subdiv[i]), size * (1.0f + 1e-6f));  // every patch edge within target
  }
}

}  // namespace
}  // namespace bp
