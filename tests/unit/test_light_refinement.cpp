// Patches that follow the light (render/light_refinement.h, docs/design.md §12): the shadowed share of a
// patch's light, and the refinement that splits the patches a shadow edge crosses, leaves evenly
// lit ones alone, keeps to its budget and gives the same layout every time.
#include "render/light_refinement.h"

#include <gtest/gtest.h>

namespace bp {
namespace {

TEST(ShadowedShare, IsTheShareOfTheLightThatSomePointsMiss) {
  // 2 samples x 4 points: the first lights every point; the second, three times as strong, only two
  const double unshadowed[] = {1, 1, 1, 1, 3, 3, 3, 3};
  const std::uint8_t all[] = {1, 1, 1, 1, 1, 1, 1, 1};
  const std::uint8_t edge[] = {1, 1, 1, 1, 1, 0, 1, 0};
  const std::uint8_t dark[] = {0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_DOUBLE_EQ(shadowed_share(unshadowed, all, 2, 4), 0.0);
  EXPECT_DOUBLE_EQ(shadowed_share(unshadowed, edge, 2, 4), 0.75);
  EXPECT_DOUBLE_EQ(shadowed_share(unshadowed, dark, 2, 4), 0.0);  // in full shadow: evenly dark
  // a point that a sample cannot light (the light behind it) neither sees it nor misses it
  const double behind[] = {1, 1, 1, 0};
  const std::uint8_t three[] = {1, 1, 1, 0};
  EXPECT_DOUBLE_EQ(shadowed_share(behind, three, 1, 4), 0.0);
}

TEST(LightRefinement, LeavesTheSoftShadowsOfWideEmittersToThePatches) {
  Light panel{};
  panel.type = BP_LIGHT_TRIANGLE;
  panel.edge1[0] = 0.5f;  // a 0.5 m triangle at the origin
  panel.edge2[1] = 0.5f;
  EXPECT_TRUE(casts_soft_shadows(panel, glm::vec3(0.2f, 0.2f, -2.0f)));    // 2 m away: 0.25 of it
  EXPECT_FALSE(casts_soft_shadows(panel, glm::vec3(0.2f, 0.2f, -20.0f)));  // 20 m: 0.025
  Light lamp{};
  lamp.type = BP_LIGHT_POINT;
  EXPECT_FALSE(casts_soft_shadows(lamp, glm::vec3(0.0f, 0.0f, -0.1f)));
  Light sky{};
  sky.type = BP_LIGHT_ENVIRONMENT;
  EXPECT_TRUE(casts_soft_shadows(sky, glm::vec3(0.0f)));
}

// A 4 x 4 m floor (two triangles, each split k = 2 by --patch-size 3) under a point light 2 m up,
// and a 0.5 m square "table top" 0.5 m above the floor's centre, facing up, that shades part of it.
Scene floor_under_a_table(bool with_table) {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(0.5f);
  scene.materials = {grey};
  const glm::vec3 a(-2, -2, 0), b(2, -2, 0), c(2, 2, 0), d(-2, 2, 0);
  scene.triangles.push_back({{a, b, c}, 0});
  scene.triangles.push_back({{a, c, d}, 0});
  if (with_table) {
    const float h = 0.5f, r = 0.25f;
    const glm::vec3 e(-r, -r, h), f(r, -r, h), g(r, r, h), i(-r, r, h);
    scene.triangles.push_back({{e, f, g}, 0});
    scene.triangles.push_back({{e, g, i}, 0});
  }
  ScenePunctualLight lamp;
  lamp.position = glm::vec3(0.3f, 0.2f, 2.0f);
  lamp.intensity = glm::vec3(10.0f);
  scene.lights.push_back(lamp);
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.bounds.grow(glm::vec3(0, 0, 2));
  return scene;
}

LightRefinementOptions generous(const PatchLayout& layout) {
  LightRefinementOptions o;
  o.levels = 2;
  o.min_patch_size = 0.01f;
  o.max_patches = 100 * std::uint64_t(layout.patch_count);
  return o;
}

TEST(LightRefinement, SplitsTheFloorATableShadesAndNotTheEvenlyLitTableTop) {
  const Scene scene = floor_under_a_table(true);
  const FlatBvh bvh = build_bvh(scene.triangles);
  PatchLayout layout = build_patch_layout(scene, 3.0f);
  ASSERT_EQ(layout.subdiv[0], 2u);
  ASSERT_EQ(layout.subdiv[2], 1u);
  const LightRefinementResult r = refine_patches_by_light(scene, layout, bvh, generous(layout));
  // both floor triangles hold part of the table's shadow edge (it crosses the diagonal): two levels
  EXPECT_EQ(layout.subdiv[0], 8u);
  EXPECT_EQ(layout.subdiv[1], 8u);
  EXPECT_EQ(layout.subdiv[2], 1u);  // the top sees the lamp from every point
  EXPECT_EQ(layout.subdiv[3], 1u);
  EXPECT_EQ(r.refined_triangles, 2u);
  EXPECT_EQ(r.patches_before, 2u * 4u + 2u);
  EXPECT_EQ(layout.patch_count, 2u * 64u + 2u);
  EXPECT_EQ(layout.first_patch[1], 64u);
  EXPECT_EQ(layout.first_patch[3], 129u);
  EXPECT_FALSE(r.budget_reached);

  PatchLayout again = build_patch_layout(scene, 3.0f);
  refine_patches_by_light(scene, again, bvh, generous(again));
  EXPECT_EQ(again.subdiv, layout.subdiv);  // a function of the scene
}

TEST(LightRefinement, LeavesAnUnshadowedFloorAlone) {
  const Scene scene = floor_under_a_table(false);
  const FlatBvh bvh = build_bvh(scene.triangles);
  PatchLayout layout = build_patch_layout(scene, 3.0f);
  const LightRefinementResult r = refine_patches_by_light(scene, layout, bvh, generous(layout));
  EXPECT_EQ(r.refined_triangles, 0u);
  EXPECT_EQ(layout.subdiv, (std::vector<std::uint32_t>{2u, 2u}));
}

TEST(LightRefinement, KeepsToItsBudgetAndItsSmallestPatch) {
  const Scene scene = floor_under_a_table(true);
  const FlatBvh bvh = build_bvh(scene.triangles);
  PatchLayout layout = build_patch_layout(scene, 3.0f);
  LightRefinementOptions o = generous(layout);
  o.max_patches = layout.patch_count + 12;  // one floor triangle's first split (3 k^2 = 12 patches)
  const LightRefinementResult r = refine_patches_by_light(scene, layout, bvh, o);
  EXPECT_TRUE(r.budget_reached);
  EXPECT_EQ(r.refined_triangles, 1u);
  EXPECT_EQ(layout.patch_count, r.patches_before + 12u);

  PatchLayout coarse = build_patch_layout(scene, 3.0f);
  o = generous(coarse);
  o.min_patch_size = 1.0f;  // the floor's patches (edges of 2.8 m, halved: 1.4 m) split once, not twice
  refine_patches_by_light(scene, coarse, bvh, o);
  EXPECT_EQ(coarse.subdiv[0], 4u);
}

}  // namespace
}  // namespace bp
