#include "scene/patches.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bp {

float default_patch_size(const Scene& scene) {
  return kDefaultPatchFraction * glm::length(scene.bounds.extent());
}

float default_cluster_size(const Scene& scene) {
  return kDefaultClusterFraction * glm::length(scene.bounds.extent());
}

namespace {
constexpr std::uint64_t kMaxPatches = std::uint64_t(1) << 31;
[[noreturn]] void throw_too_many_patches(float target_size) {
  throw std::invalid_argument("--patch-size " + std::to_string(target_size) +
                              " m gives more than 2^31 patches; choose a larger size");
}
}  // namespace

PatchLayout build_patch_layout(const Scene& scene, float target_size, float cluster_size) {
  if (!(target_size > 0.0f) || !std::isfinite(target_size))
    throw std::invalid_argument("--patch-size must be a positive finite length in metres (got " +
                                std::to_string(target_size) + ")");
  PatchLayout layout;
  layout.target_size = target_size;
  if (cluster_size > 0.0f) layout.clusters = build_patch_clusters(scene, cluster_size);
  const std::size_t triangles = patch_triangle_count(scene, layout);
  layout.subdiv.reserve(triangles);
  for (std::size_t i = 0; i < triangles; ++i) {
    const SceneTriangle& t = patch_triangle(scene, layout, i);
    if (i < scene.triangles.size() && !layout.clusters.fans.empty() && layout.clusters.fan_count[i] > 0) {
      layout.subdiv.push_back(0u);  // its cluster's fan owns its patches
      continue;
    }
    const float longest = std::max({glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]),
                                    glm::length(t.p[0] - t.p[2])});
    const double k = std::max(1.0, std::ceil(double(longest) / double(target_size)));
    if (!(k * k <= double(kMaxPatches))) throw_too_many_patches(target_size);
    layout.subdiv.push_back(std::uint32_t(k));
  }
  number_patches(scene, layout);
  return layout;
}

void number_patches(const Scene& scene, PatchLayout& layout) {
  const std::size_t triangles = patch_triangle_count(scene, layout);
  layout.first_patch.assign(triangles, 0u);
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < triangles; ++i) {
    const double k = layout.subdiv[i];
    const bool two_sided = scene.materials.at(patch_triangle(scene, layout, i).material).double_sided;
    const double count = (two_sided ? 2.0 : 1.0) * k * k;
    if (!(double(total) + count <= double(kMaxPatches))) throw_too_many_patches(layout.target_size);
    layout.first_patch[i] = std::uint32_t(total);
    total += std::uint64_t(count);
  }
  layout.patch_count = std::uint32_t(total);
}

}  // namespace bp
