// Patches (docs/design.md §6): every triangle is split into k^2 sub-triangles (kernels/shared/patch.h)
// with k chosen so that every sub-triangle edge is at most the target patch size. With clusters
// (docs/design.md §12, clusters.h) a clustered scene triangle owns no patches (k = 0) and its cluster's
// fan triangles, numbered after the scene's, own them: the "patch triangles".
#pragma once
#include "scene/clusters.h"
#include "scene/scene.h"
#include "kernels/shared/patch.h"
#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace bp {

struct PatchLayout {
  float target_size = 0.0f;               // metres
  std::vector<std::uint32_t> first_patch; // per patch triangle
  std::vector<std::uint32_t> subdiv;      // per patch triangle: k (0: a clustered scene triangle)
  std::uint32_t patch_count = 0;          // front patches, plus back patches of double-sided triangles
  PatchClusters clusters;                 // empty fans: none
};

// The scene's triangles, then the clusters' fan triangles.
inline std::size_t patch_triangle_count(const Scene& scene, const PatchLayout& patches) {
  return scene.triangles.size() + patches.clusters.fans.size();
}
inline const SceneTriangle& patch_triangle(const Scene& scene, const PatchLayout& patches, std::size_t t) {
  return t < scene.triangles.size() ? scene.triangles[t] : patches.clusters.fans[t - scene.triangles.size()];
}
// The scene triangle a patch triangle stands for (a fan: one triangle of its cluster).
inline std::size_t scene_triangle_of(const Scene& scene, const PatchLayout& patches, std::size_t t) {
  return t < scene.triangles.size() ? t : patches.clusters.fan_source[t - scene.triangles.size()];
}

// Default target patch size: kDefaultPatchFraction of the scene's bounding-box diagonal. 1/20 gives
// the Cornell box (diagonal 0.96 m, target 4.8 cm) 3734 patches (a wall triangle, longest edge the
// quad's 0.78 m diagonal, gets k = 17; the light k = 4): a few thousand, so an RB iteration stays
// cheap and the patch count scales with the scene's shape, not its units. --patch-size overrides.
inline constexpr float kDefaultPatchFraction = 1.0f / 20.0f;
float default_patch_size(const Scene& scene);
// Default largest diameter of a cluster (--patch-clusters, docs/design.md §12): kDefaultClusterFraction
// of the diagonal. 1/80 gives the 25-room house (diagonal 32 m) clusters of up to 0.4 m, where its
// RB error at 640x360 equals that of its 100 k triangles unclustered (docs/results.md, "Clusters").
inline constexpr float kDefaultClusterFraction = 1.0f / 80.0f;
float default_cluster_size(const Scene& scene);

// Throws std::invalid_argument if target_size is not positive and finite, or the patch count
// would exceed 2^31 (the message names --patch-size). cluster_size > 0: merge triangles into
// clusters of diameter at most cluster_size first (build_patch_clusters).
PatchLayout build_patch_layout(const Scene& scene, float target_size, float cluster_size = 0.0f);

// first_patch and patch_count from subdiv (after a change to subdiv: refine_patches_by_light).
// Throws std::invalid_argument past 2^31 patches.
void number_patches(const Scene& scene, PatchLayout& layout);

// One patch-level sub-triangle of a scene triangle, as the host-side builders (RB's elements, the
// light tree's receivers) walk them: corner c is parent.p[0] + b1[c] e1 + b2[c] e2.
struct SubTriangle {
  std::size_t triangle;        // patch triangle (patch_triangle)
  const SceneTriangle* parent; // that triangle
  std::uint32_t local;         // 0 .. k^2 - 1 (kernels/shared/patch.h)
  std::uint32_t k2;            // sub-triangles of the parent
  float b1[3], b2[3];          // the corners' barycentrics
  glm::vec3 e1, e2;            // the parent's edges p1 - p0, p2 - p0
  glm::vec3 normal;            // the parent's flat unit normal (front side)
  float parent_area2;          // |e1 x e2|: twice the parent's area, m^2
  bool double_sided;           // a back patch at first_patch + k^2 + local beside the front one
};

// Calls visit(const SubTriangle&) for every sub-triangle, triangle by triangle in patch order (of
// the triangles in [first, last) only, where given).
template <class Visit>
void for_each_sub_triangle(const Scene& scene, const PatchLayout& patches, Visit&& visit, std::size_t first = 0,
                           std::size_t last = SIZE_MAX) {
  for (std::size_t t = first; t < patch_triangle_count(scene, patches) && t < last; ++t) {
    const SceneTriangle& tri = patch_triangle(scene, patches, t);
    SubTriangle sub{};
    sub.triangle = t;
    sub.parent = &tri;
    sub.k2 = patches.subdiv[t] * patches.subdiv[t];
    sub.double_sided = scene.materials[tri.material].double_sided;
    sub.e1 = tri.p[1] - tri.p[0];
    sub.e2 = tri.p[2] - tri.p[0];
    const glm::vec3 n = glm::cross(sub.e1, sub.e2);
    sub.parent_area2 = glm::length(n);
    sub.normal = sub.parent_area2 > 0.0f ? n / sub.parent_area2 : glm::vec3(0.0f, 0.0f, 1.0f);
    for (sub.local = 0; sub.local < sub.k2; ++sub.local) {
      patch_corner_barycentrics(sub.local, patches.subdiv[t], sub.b1, sub.b2);
      visit(static_cast<const SubTriangle&>(sub));
    }
  }
}

// for_each_sub_triangle with the triangles split among the host's threads; visit must only write
// what its own sub-triangle owns.
template <class Visit> void for_each_sub_triangle_in_parallel(const Scene& scene, const PatchLayout& patches, Visit&& visit) {
  const std::size_t n = patch_triangle_count(scene, patches);
  const std::size_t threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, (n + 63) / 64);
  std::vector<std::thread> pool;
  for (std::size_t i = 0; i < threads; ++i)
    pool.emplace_back([&, i] { for_each_sub_triangle(scene, patches, visit, n * i / threads, n * (i + 1) / threads); });
  for (std::thread& t : pool) t.join();
}

}  // namespace bp
