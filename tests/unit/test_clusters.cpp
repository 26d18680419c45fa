// Patch clusters (scene/clusters.h, docs/design.md §12): flat neighbouring triangles of one plain material
// merge into convex polygons that cover exactly what they replace; what RB must see apart stays
// apart; and the path tracer's patch of a point (kernels/shared/cluster.h) is the patch whose RB
// element holds the point.
#include "kernels/shared/surface.h"
#include "device/device_scene.h"
#include "scene/bundle_geometry.h"
#include "scene/clusters.h"
#include "scene/patches.h"

#include <gtest/gtest.h>
#include <map>
#include <random>

namespace bp {
namespace {

double area(const SceneTriangle& t) {
  return 0.5 * glm::length(glm::cross(glm::dvec3(t.p[1] - t.p[0]), glm::dvec3(t.p[2] - t.p[0])));
}

// The unit square [0,1]^2 in z = `z`, facing +z, as n x n cells of two triangles (make_rooms' way);
// material(i, j) of cell (i, j).
template <class MaterialOf>
void add_grid(Scene& scene, int n, float z, MaterialOf material) {
  auto at = [&](int i, int j) { return glm::vec3(float(i) / n, float(j) / n, z); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t m = material(i, j);
      scene.triangles.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}, m});
      scene.triangles.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}, m});
    }
}

void grow_bounds(Scene& scene) {
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
}

Scene grid_square(int n, bool double_sided = false) {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(0.5f);
  grey.double_sided = double_sided;
  scene.materials = {grey};
  add_grid(scene, n, 0.0f, [](int, int) { return 0u; });
  grow_bounds(scene);
  return scene;
}

// Every cluster: its fan covers what its triangles cover (equal areas: the union is its convex hull),
// in their plane, facing their way, of their material.
void expect_clusters_cover_their_triangles(const Scene& scene, const PatchClusters& c) {
  std::map<std::uint32_t, double> member_area;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    if (c.fan_count[t] == 0) continue;
    member_area[c.fan_first[t]] += area(scene.triangles[t]);
    const SceneTriangle& fan = c.fans[c.fan_first[t]];
    EXPECT_EQ(fan.material, scene.triangles[t].material) << "triangle " << t;
    const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(fan.p[1] - fan.p[0]), glm::dvec3(fan.p[2] - fan.p[0])));
    const glm::dvec3 m = glm::normalize(glm::cross(glm::dvec3(scene.triangles[t].p[1] - scene.triangles[t].p[0]),
                                                   glm::dvec3(scene.triangles[t].p[2] - scene.triangles[t].p[0])));
    EXPECT_GT(glm::dot(n, m), 1.0 - 1e-6) << "triangle " << t << " is not in its cluster's plane, or faces away";
  }
  for (const auto& [first, members] : member_area) {
    double fans = 0.0;
    std::uint32_t count = 0;
    for (std::size_t t = 0; t < scene.triangles.size(); ++t)
      if (c.fan_count[t] > 0 && c.fan_first[t] == first) count = c.fan_count[t];
    ASSERT_GE(count, 1u);
    ASSERT_LE(count, kMaxClusterCorners - 2);
    for (std::uint32_t i = 0; i < count; ++i) fans += area(c.fans[first + i]);
    EXPECT_NEAR(fans, members, 1e-5 * members) << "cluster at fan " << first;
  }
}

TEST(Clusters, MergeAFinelyTessellatedSquareIntoRectanglesThatCoverItExactly) {
  const Scene scene = grid_square(8);  // cells of 0.125 m
  // 0.4 m: two by two cells (0.354 m across) fit, two by three (0.451 m) do not
  const PatchClusters c = build_patch_clusters(scene, 0.4f);
  EXPECT_EQ(c.clustered_triangles, scene.triangles.size());
  EXPECT_EQ(c.clusters, 16u) << "the 8 x 8 grid in 2 x 2 blocks";
  expect_clusters_cover_their_triangles(scene, c);
  double total = 0.0;
  for (const SceneTriangle& f : c.fans) {
    total += area(f);
    EXPECT_LE(glm::length(f.p[1] - f.p[0]), 0.4f + 1e-6f);
    EXPECT_LE(glm::length(f.p[2] - f.p[1]), 0.4f + 1e-6f);
    EXPECT_LE(glm::length(f.p[0] - f.p[2]), 0.4f + 1e-6f);
  }
  EXPECT_NEAR(total, 1.0, 1e-6);
  // the same scene gives the same clusters (the render is a pure function of scene and seed)
  const PatchClusters again = build_patch_clusters(scene, 0.4f);
  ASSERT_EQ(again.fans.size(), c.fans.size());
  for (std::size_t i = 0; i < c.fans.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(again.fans[i].p[k], c.fans[i].p[k]);
  EXPECT_EQ(again.fan_first, c.fan_first);
}

TEST(Clusters, KeepApartWhatTheBundlesMustSeeApart) {
  Scene scene;
  SceneMaterial a, b, light, textured;
  a.kd = glm::vec3(0.5f);
  b.kd = glm::vec3(0.2f);
  light.emission = glm::vec3(1.0f);
  textured.kd = glm::vec3(0.5f);
  textured.textures.base_color = 0;  // a base colour texture
  scene.materials = {a, b, light, textured};
  add_grid(scene, 6, 0.0f, [](int i, int j) { return std::uint32_t((i / 2 + j / 2) % 2); });  // 2x2-cell checkers
  const std::size_t checkers = scene.triangles.size();
  add_grid(scene, 4, 1.0f, [](int, int) { return 2u; });  // emitters
  add_grid(scene, 4, 2.0f, [](int, int) { return 3u; });  // textured
  // a fold: the square's 4 x 4 grid in z = 3 and the same turned up about its edge x = 1
  const std::size_t fold = scene.triangles.size();
  add_grid(scene, 4, 3.0f, [](int, int) { return 0u; });
  for (std::size_t t = fold, end = scene.triangles.size(); t < end; ++t) {
    SceneTriangle up = scene.triangles[t];
    for (glm::vec3& p : up.p) p = glm::vec3(1.0f, p.y, 3.0f + p.x);
    std::swap(up.p[1], up.p[2]);  // (winding kept facing -x)
    scene.triangles.push_back(up);
  }
  grow_bounds(scene);
  const PatchClusters c = build_patch_clusters(scene, 10.0f);
  expect_clusters_cover_their_triangles(scene, c);  // one material and plane per cluster
  for (std::size_t t = checkers; t < fold; ++t) EXPECT_EQ(c.fan_count[t], 0u) << "emitter or textured triangle " << t;
  EXPECT_GT(c.clusters, 0u);
  // the checkers: each 2 x 2-cell square of one material is one cluster (nothing joins across materials)
  std::map<std::uint32_t, int> members;
  for (std::size_t t = 0; t < checkers; ++t) ++members[c.fan_first[t]];
  EXPECT_EQ(members.size(), 9u);
  // the fold's two halves: no cluster holds both
  std::map<std::uint32_t, int> sides;
  for (std::size_t t = fold; t < scene.triangles.size(); ++t) {
    ASSERT_GT(c.fan_count[t], 0u);
    sides[c.fan_first[t]] |= t < fold + 32 ? 1 : 2;
  }
  for (const auto& [first, mask] : sides) EXPECT_NE(mask, 3) << "a cluster across the fold";
}

// An L of three cells (its hull would cover the missing fourth): clusters stay convex, so not one.
TEST(Clusters, NeverCoverWhatIsNotThere) {
  Scene scene = grid_square(2);
  scene.triangles.erase(scene.triangles.begin() + 6, scene.triangles.end());  // cell (1, 1) gone
  const PatchClusters c = build_patch_clusters(scene, 10.0f);
  EXPECT_GT(c.clusters, 0u);
  expect_clusters_cover_their_triangles(scene, c);
  std::map<std::uint32_t, double> cluster_area;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    if (c.fan_count[t] > 0) cluster_area[c.fan_first[t]] += area(scene.triangles[t]);
  for (const auto& [first, a] : cluster_area) EXPECT_LT(a, 0.75 - 1e-3) << "one cluster over the whole L";
}

// Points on clustered triangles, front and back: the path tracer's patch (surface_at through the
// fans) is one whose RB element holds the point, on the side the ray came from.
TEST(Clusters, ThePathTracerAndTheBundlesAgreeOnEveryPointsPatch) {
  const Scene scene = grid_square(12, true);
  const PatchLayout patches = build_patch_layout(scene, 0.2f, 0.3f);
  ASSERT_GT(patches.clusters.clusters, 0u);
  const BundleGeometry geometry = build_bundle_geometry(scene, patches);
  const std::vector<TriangleShading> shading = pack_triangle_shading(scene, patches);
  const std::vector<ClusterFan> fans = pack_cluster_fans(scene, patches);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int checked = 0;
  for (int i = 0; i < 4000; ++i) {
    const std::uint32_t t = std::uint32_t(rng() % scene.triangles.size());
    float b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1.0f) {
      b1 = 1.0f - b1;
      b2 = 1.0f - b2;
    }
    const SceneTriangle& tri = scene.triangles[t];
    const glm::vec3 p = tri.p[0] + b1 * (tri.p[1] - tri.p[0]) + b2 * (tri.p[2] - tri.p[0]);
    const bool front = i % 2 == 0;
    const float3 dir = make_float3(0.0f, 0.0f, front ? -1.0f : 1.0f);
    const SurfaceHit s = surface_at(shading.data(), fans.data(), t, b1, b2, make_float3(p.x, p.y, p.z), dir);
    ASSERT_LT(s.patch, geometry.patch_element.size());
    const std::uint32_t slot = geometry.patch_element[s.patch];
    EXPECT_EQ((slot & kBackSidePatch) == 0, front) << "patch " << s.patch << " is on the other side";
    const BundleElement& el = geometry.elements[slot & ~kBackSidePatch];
    // the point's barycentrics in the element (its plane is the triangle's)
    const glm::dvec3 v0(el.v0[0], el.v0[1], el.v0[2]), e1(el.e1[0], el.e1[1], el.e1[2]), e2(el.e2[0], el.e2[1], el.e2[2]);
    const glm::dvec3 n = glm::cross(e1, e2), d = glm::dvec3(p) - v0;
    const double l1 = glm::dot(glm::cross(d, e2), n) / glm::dot(n, n), l2 = glm::dot(glm::cross(e1, d), n) / glm::dot(n, n);
    const double tolerance = 1e-4;
    EXPECT_TRUE(l1 > -tolerance && l2 > -tolerance && l1 + l2 < 1.0 + tolerance)
        << "point (" << p.x << ", " << p.y << ") on triangle " << t << " given patch " << s.patch << " (l " << l1 << ", "
        << l2 << ")";
    ++checked;
  }
  EXPECT_EQ(checked, 4000);
}

}  // namespace
}  // namespace bp
