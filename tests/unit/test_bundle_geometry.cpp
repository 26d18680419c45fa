// Element geometry of the ray-bundle pass: sub-triangle barycentrics and Gouraud vertex welding.
#include "scene/bundle_geometry.h"
#include "kernels/shared/patch.h"

#include <gtest/gtest.h>
#include <random>
#include <set>

namespace bp {
namespace {

TEST(PatchBarycentrics, LocalBarycentricsReconstructThePoint) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (bp_u32 k = 1; k <= 9; ++k)
    for (int i = 0; i < 2000; ++i) {
      float b1 = u(rng), b2 = u(rng);
      if (b1 + b2 > 1.0f) { b1 = 1.0f - b1; b2 = 1.0f - b2; }
      float l1, l2, c1[3], c2[3];
      patch_local_barycentrics(b1, b2, k, &l1, &l2);
      patch_corner_barycentrics(patch_local_index(b1, b2, k), k, c1, c2);
      EXPECT_GE(l1, -1e-4f);
      EXPECT_GE(l2, -1e-4f);
      EXPECT_LE(l1 + l2, 1.0f + 1e-4f);
      float r1 = (1 - l1 - l2) * c1[0] + l1 * c1[1] + l2 * c1[2];
      float r2 = (1 - l1 - l2) * c2[0] + l1 * c2[1] + l2 * c2[2];
      EXPECT_NEAR(r1, b1, 1e-5f) << "k = " << k;
      EXPECT_NEAR(r2, b2, 1e-5f) << "k = " << k;
    }
}

Scene unit_quad(bool double_sided) {
  Scene s;
  SceneMaterial m;
  m.double_sided = double_sided;
  s.materials = {m};
  s.triangles.push_back({{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 0});
  s.triangles.push_back({{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 0});
  for (const auto& t : s.triangles)
    for (const auto& p : t.p) s.bounds.grow(p);
  return s;
}

TEST(BundleGeometry, QuadWeldsIntoAGridOfVertices) {
  Scene s = unit_quad(false);
  PatchLayout layout = build_patch_layout(s, 0.25f);  // diagonal 1.41 -> k = 6
  ASSERT_EQ(layout.subdiv[0], 6u);
  BundleGeometry g = build_bundle_geometry(s, layout);
  EXPECT_EQ(g.elements.size(), 72u);
  EXPECT_EQ(g.vertex_patch_start.size() - 1, 49u);  // (k + 1)^2: the shared diagonal welds
  EXPECT_NEAR(g.element_area, 1.0, 1e-5);
  // Every patch appears under each of its three vertices.
  EXPECT_EQ(g.vertex_patches.size(), 3 * g.patch_element.size());
}

TEST(BundleGeometry, DoubleSidedBacksAreTheirOwnPatchesAndVertices) {
  Scene s = unit_quad(true);
  PatchLayout layout = build_patch_layout(s, 0.25f);
  BundleGeometry g = build_bundle_geometry(s, layout);
  EXPECT_EQ(g.patch_element.size(), 144u);
  EXPECT_EQ(g.vertex_patch_start.size() - 1, 98u);  // front and back grids do not weld
  std::set<std::uint32_t> backs;
  for (const BundleElement& el : g.elements) {
    ASSERT_NE(el.back_patch, BP_NO_PATCH);
    EXPECT_EQ(g.patch_element[el.back_patch] & kBackSidePatch, kBackSidePatch);
    backs.insert(el.back_patch);
  }
  EXPECT_EQ(backs.size(), 72u);
}

}  // namespace
}  // namespace bp
