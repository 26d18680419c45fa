// The combination over clustered patches (scene/clusters.h, docs/design.md §12) agrees with the path
// tracer, which never sees the clusters: RB transfers, gathers and weighs per cluster, PT finds the
// same cluster's patch for its weight inputs (kernels/shared/cluster.h), and the sum stays unbiased.
#include "kernel/power_test.h"

#include <gtest/gtest.h>

namespace bp::test {
namespace {

// The glossy light box (a glossy floor under a small light) with every wall and the floor split into
// 8 x 8 x 2 triangles of 0.125 m, merged back into clusters of at most 0.25 m, then patches of 0.05 m.
TEST(ClusteredCombination, MatchesThePathTracerWithThePowerToSeeTwoPercent) {
  const Scene scene = subdivide_non_emitters(make_glossy_light_box(), 8);
  const float cluster_size = 0.25f;
  const PatchLayout patches = build_patch_layout(scene, 0.05f, cluster_size);
  ASSERT_EQ(patches.clusters.clustered_triangles, scene.triangles.size() - 2) << "all but the light's two";
  expect_combination_matches_pt_with_power_to_see_two_percent(scene, "clustered glossy box", cluster_size);
}

}  // namespace
}  // namespace bp::test
