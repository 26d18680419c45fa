// The weighted combination on the test device: --weights product converges to the path-traced
// reference (per-region t-tests at the run's sample counts), the error keeps falling with longer
// runs, and the plain sum (--weights none) is caught as biased.
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"

#include <gtest/gtest.h>
#include <cmath>
#include <string>

namespace bp::test {
namespace {

CombinedRun combined_run(const Scene& scene, std::uint32_t mode, std::uint64_t rounds, std::uint32_t seed,
                         bool light_sampling = false, std::uint32_t beta_heuristic = BP_BETA_CLAMPED,
                         float light_rate = 1.0f, std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE,
                         bool eye_direct_shared = false) {
  CombinedSettings cs;
  cs.light_selection = light_selection;
  cs.eye_direct_shared = eye_direct_shared;
  cs.beta_heuristic = beta_heuristic;
  cs.light_rate = light_rate;
  cs.light_sampling = light_sampling;
  cs.weight_mode = mode;
  cs.seed = seed;
  cs.rounds = rounds;
  cs.patch_size = 0.05f;
  return render_combined(scene, kSize, kSize, cs);
}

// A glossy floor under a small light: the combination with the product weights (either beta)
// converges to the path tracer's answer -- no 8x8 block, channel or image level differs significantly
// between 8 independent combined runs and 8 independent path-traced runs -- while the same test
// catches the plain sum (--weights none, every path counted twice).
TEST(Combination, ProductWeightsConvergeToThePathTracedReferenceAndThePlainSumDoesNot) {
  Scene scene = make_glossy_light_box();
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 512, seed).image; });
  for (std::uint32_t beta : {BP_BETA_CLAMPED, BP_BETA_BALANCE}) {
    Sample product = independent_runs(runs, [&](std::uint32_t seed) {
      return combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 1, false, beta).combined;  // 64 spp + 256 iterations
    });
    for (const std::string& d : significant_differences(product, reference, runs))
      ADD_FAILURE() << "product weights, beta " << (beta == BP_BETA_CLAMPED ? "clamped" : "balance") << ", " << d;
  }
  Sample none = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_NONE, 64, seed + 1).combined;
  });
  EXPECT_FALSE(significant_differences(none, reference, runs).empty()) << "the plain sum was not caught";
}

// Light sampling as a further strategy (DESIGN.md §3): the four techniques of the last segment keep
// the product combination unbiased, for an area light and for a point light (which only the PT and
// RB light samples reach), with every patch tracing its light sample each iteration and with a
// quarter of them (the rate large scenes get; the weights count rate x N2 RB light samples).
// Lights chosen by the light tree (the default) or by power; the reference is PT choosing by power.
// The eye vertex's direct light PT's alone (eye_shared false) or shared with RB (--eye-direct shared).
void expect_light_sampled_combination_unbiased(const Scene& scene, float light_rate, bool eye_shared,
                                               std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE) {
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 256, seed, 65536, true, BP_LIGHT_SELECTION_POWER).image;
  });
  Sample combined = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 1, true, BP_BETA_CLAMPED, light_rate, light_selection,
                        eye_shared)
        .combined;
  });
  for (const std::string& d : significant_differences(combined, reference, runs))
    ADD_FAILURE() << "RB light rate " << light_rate << ", selection "
                  << (light_selection == BP_LIGHT_SELECTION_TREE ? "tree" : "power")
                  << (eye_shared ? ", eye direct shared, " : ", ") << d;
}

TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderAnAreaLight) {
  expect_light_sampled_combination_unbiased(make_glossy_light_box(), 1.0f, false);
  expect_light_sampled_combination_unbiased(make_glossy_light_box(), 0.25f, true);
}

// Five lights of every kind, some behind a partition: with the light tree, p_L differs per receiving
// patch, and PT and RB must still evaluate the same one (DESIGN.md §3, light selection).
TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderManyLightsChosenByTheTree) {
  expect_light_sampled_combination_unbiased(make_multi_light_box(), 0.25f, true, BP_LIGHT_SELECTION_TREE);
}

TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderManyLightsChosenByPower) {
  expect_light_sampled_combination_unbiased(make_multi_light_box(), 0.25f, false, BP_LIGHT_SELECTION_POWER);
}

TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderAPointLight) {
  Scene scene = make_glossy_light_box();
  for (SceneMaterial& m : scene.materials) m.emission = glm::vec3(0.0f);
  ScenePunctualLight point;
  point.position = glm::vec3(0.1f, 0.3f, -0.1f);
  point.intensity = glm::vec3(1.0f, 0.8f, 0.6f);
  scene.lights.push_back(point);
  expect_light_sampled_combination_unbiased(scene, 0.25f, true);
}

TEST(Combination, ErrorKeepsFallingAsTheRunGetsLonger) {
  Scene scene = make_glossy_light_box();
  Sample reference = independent_runs(8, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 512, seed).image; });
  double short_error = 0.0, long_error = 0.0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    short_error += relative_mse(combined_run(scene, BP_WEIGHTS_PRODUCT, 8, seed).combined, reference.mean) / 4;
    long_error += relative_mse(combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 10).combined, reference.mean) / 4;
  }
  // 8x the samples: the variance part falls 8x; what stays is the reference's own noise and RB's
  // discretisation, both far below the short runs' error.
  EXPECT_LT(long_error, 0.4 * short_error) << "relMSE " << short_error << " -> " << long_error;
}

}  // namespace
}  // namespace bp::test
