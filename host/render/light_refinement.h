// Patches that follow the light (docs/design.md §12): a patch triangle across which the direct light's
// visibility changes -- a shadow edge, a contact shadow, the sun's patch through a window -- is
// split further, so RB's patch-level light can follow what the path tracer sees per pixel. Done once
// on the host before the render, from the scene alone: the layout is a pure function of the scene
// and the options (checkpoints, ranks and walkthroughs see the same patches).
#pragma once
#include "kernels/shared/lights.h"
#include "scene/bvh.h"
#include "scene/patches.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>

namespace bp {

// Emitting triangles wider than this times their distance cast soft shadows, which refinement
// leaves to the patches (casts_soft_shadows).
inline constexpr float kSharpShadowRatio = 0.1f;

struct LightRefinementOptions {
  std::uint32_t levels = 2;        // each level halves a refined triangle's patches' edges
  float min_patch_size = 0.0f;     // metres: no patch is split below it
  std::uint64_t max_patches = 0;   // the budget: refinement stops before the layout passes it
  float split_above = 0.25f;       // the shadowed share (below) at which a patch is split
  std::uint32_t light_samples = 8; // light samples per patch triangle, shared by all its points
};

struct LightRefinementResult {
  std::size_t refined_triangles = 0;  // patch triangles split at least once
  std::uint32_t patches_before = 0;
  bool budget_reached = false;        // a triangle that asked for a split was left as it was
};

// The share of a patch's direct light that is shadowed on part of it, from shared light samples
// j (chosen by the light tree for the patch triangle) seen from the patch's corners and centroid i:
//   S = sum_j g_j (max_i V_ij - min_i V_ij) / sum_j g_j max_i V_ij,
// g_j the sample's unshadowed irradiance estimate averaged over the points, V_ij its visibility.
// S = 0 where every point sees the same lights, 1 where a shadow edge crosses all of its light.
// One function of the four points' visibilities, for the tests to call.
double shadowed_share(const double* unshadowed, const std::uint8_t* visible, std::size_t samples, std::size_t points);

// The defaults: two levels, no patch below the scene's diagonal / kMinPatchFraction nor below
// kMinPatchBins bins of the unrefined layout's default buffer, at most kPatchBudgetFactor times
// the unrefined layout's patches.
inline constexpr float kMinPatchFraction = 640.0f;
inline constexpr float kMinPatchBins = 2.0f;
inline constexpr std::uint64_t kPatchBudgetFactor = 2;
LightRefinementOptions light_refinement_options(const Scene& scene, const PatchLayout& layout);

// Whether a light's shadows on a receiver at `at` are soft, so that refinement leaves them to the
// patches: the environment, and an emitting triangle wider than kSharpShadowRatio times its
// distance, whose penumbrae are wide wherever the occluder is not at the receiver (measured: the
// house's ceiling panels gain nothing from finer patches, docs/results.md). Points, spots and suns
// cast sharp shadows.
bool casts_soft_shadows(const Light& light, const glm::vec3& at);

// Splits (subdiv *= 2, per level) every patch triangle with a patch whose shadowed_share exceeds
// options.split_above while the budget lasts, first those whose split makes the most shadowed
// area (share times area, summed over the patches) per patch it adds, and renumbers the patches.
// Deterministic: the same scene and options give the same layout on every host and thread count.
LightRefinementResult refine_patches_by_light(const Scene& scene, PatchLayout& layout, const FlatBvh& bvh,
                                              const LightRefinementOptions& options);

}  // namespace bp
