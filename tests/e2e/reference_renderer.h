// An independent CPU path tracer for end-to-end tests. Plain double-precision C++ that shares no
// sampling, BRDF, RNG or BVH code with the renderer it checks; only bp::Scene is common. It follows
// the scene conventions of docs/design.md §6: modified Phong, one-sided emitters and surfaces (both sides
// when the material is double_sided), the pinhole camera of bp::SceneCamera with y = 0 at the top.
#pragma once
#include "image/image.h"
#include "scene/scene.h"

#include <glm/glm.hpp>
#include <cstdint>

namespace bp {

enum class ReferenceEstimator {
  hemisphere,      // uniform hemisphere sampling only; emission is counted where a path hits it
  hemisphere_nee,  // the same walk, but direct light comes from emitters sampled uniformly by area
};

struct ReferenceOptions {
  ReferenceEstimator estimator = ReferenceEstimator::hemisphere_nee;
  int threads = 0;  // 0: std::thread::hardware_concurrency()
};

struct ReferenceResult {
  ImageRGB mean;           // per-pixel radiance estimate (mean of spp path samples)
  // Per-pixel standard error of that mean: sample std-dev / sqrt(spp). Path sums are skewed, so at
  // a few hundred spp it underestimates in some pixels; z-test blocks of pixels, or use >= ~2k spp.
  ImageRGB std_error;
  double seconds = 0.0;    // wall-clock render time
  std::uint64_t paths = 0; // width * height * spp
  std::uint64_t rays = 0;  // every ray traced, shadow rays included
};

// Deterministic for a given seed, whatever the thread count. The image aspect is width/height
// (SceneCamera::aspect is not used). spp >= 2 so that a variance can be estimated.
ReferenceResult render_reference(const Scene& scene, int width, int height, int spp, std::uint64_t seed,
                                  const ReferenceOptions& options = {});

namespace reference_detail {
// Modified Phong f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha), alpha between wi and the mirror of wo
// about the normal; 0 unless wi and wo both lie on the normal's side. Exposed for its unit test.
glm::dvec3 phong_brdf(const SceneMaterial& material, const glm::dvec3& normal, const glm::dvec3& wo,
                      const glm::dvec3& wi);
}  // namespace reference_detail

}  // namespace bp
