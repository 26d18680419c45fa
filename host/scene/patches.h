// Patches (DESIGN.md §6): every triangle is split into k^2 sub-triangles (kernels/shared/patch.h)
// with k chosen so that every sub-triangle edge is at most the target patch size.
#pragma once
#include "scene/scene.h"
#include <cstdint>
#include <vector>

namespace bp {

struct PatchLayout {
  float target_size = 0.0f;               // metres
  std::vector<std::uint32_t> first_patch; // per triangle
  std::vector<std::uint32_t> subdiv;      // per triangle: k
  std::uint32_t patch_count = 0;          // front patches, plus back patches of double-sided triangles
};

// Default target patch size: kDefaultPatchFraction of the scene's bounding-box diagonal. 1/20 gives
// the Cornell box (diagonal 0.96 m, target 4.8 cm) 3734 patches (a wall triangle, longest edge the
// quad's 0.78 m diagonal, gets k = 17; the light k = 4): a few thousand, so an RB iteration stays
// cheap and the patch count scales with the scene's shape, not its units. --patch-size overrides.
inline constexpr float kDefaultPatchFraction = 1.0f / 20.0f;
float default_patch_size(const Scene& scene);

// Throws std::invalid_argument if target_size is not positive and finite, or the patch count
// would exceed 2^31 (the message names --patch-size).
PatchLayout build_patch_layout(const Scene& scene, float target_size);

}  // namespace bp
