#include "scene/patches.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bp {

float default_patch_size(const Scene& scene) {
  return kDefaultPatchFraction * glm::length(scene.bounds.extent());
}

PatchLayout build_patch_layout(const Scene& scene, float target_size) {
  if (!(target_size > 0.0f) || !std::isfinite(target_size))
    throw std::invalid_argument("--patch-size must be a positive finite length in metres (got " +
                                std::to_string(target_size) + ")");
  constexpr std::uint64_t kMaxPatches = std::uint64_t(1) << 31;
  PatchLayout layout;
  layout.target_size = target_size;
  layout.first_patch.reserve(scene.triangles.size());
  layout.subdiv.reserve(scene.triangles.size());
  std::uint64_t total = 0;
  for (const SceneTriangle& t : scene.triangles) {
    const float longest = std::max({glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]),
                                    glm::length(t.p[0] - t.p[2])});
    const double k = std::max(1.0, std::ceil(double(longest) / double(target_size)));
    const bool two_sided = scene.materials.at(t.material).double_sided;
    const double count = (two_sided ? 2.0 : 1.0) * k * k;
    if (!(double(total) + count <= double(kMaxPatches)))
      throw std::invalid_argument("--patch-size " + std::to_string(target_size) +
                                  " m gives more than 2^31 patches; choose a larger size");
    layout.first_patch.push_back(std::uint32_t(total));
    layout.subdiv.push_back(std::uint32_t(k));
    total += std::uint64_t(count);
  }
  layout.patch_count = std::uint32_t(total);
  return layout;
}

}  // namespace bp
