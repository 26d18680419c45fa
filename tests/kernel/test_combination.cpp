// The weighted combination on the test device: --weights product converges to the path-traced
// reference (per-region t-tests at the run's sample counts), the error keeps falling with longer
// runs, and the plain sum (--weights none) is caught as biased; the image mean and quadrants of many
// cheap runs match the reference with the power to see a 2 % bias (issue #12).
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"

#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

namespace bp::test {
namespace {

CombinedRun combined_run(const Scene& scene, std::uint32_t mode, std::uint64_t rounds, std::uint32_t seed,
                         bool light_sampling = false, std::uint32_t beta_heuristic = BP_BETA_CLAMPED,
                         float light_rate = 1.0f, std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE,
                         bool eye_direct_shared = false, std::uint32_t pt_samples_per_round = 1,
                         std::uint32_t rb_iterations_per_round = 4, bool sun_own = false) {
  CombinedSettings cs;
  cs.sun_own = sun_own;
  cs.light_selection = light_selection;
  cs.eye_direct_shared = eye_direct_shared;
  cs.pt_samples_per_round = pt_samples_per_round;
  cs.rb_iterations_per_round = rb_iterations_per_round;
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

// Light sampling as a further strategy (docs/design.md §3): the four techniques of the last segment keep
// the product combination unbiased, for an area light and for a point light (which only the PT and
// RB light samples reach), with every patch tracing its light sample each iteration and with a
// quarter of them (the rate large scenes get; the weights count rate x N2 RB light samples).
// Lights chosen by the light tree (the default) or by power; the reference is PT choosing by power.
// The eye vertex's direct light PT's alone (eye_shared false) or shared with RB (--eye-direct shared).
void expect_light_sampled_combination_unbiased(const Scene& scene, float light_rate, bool eye_shared,
                                               std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE,
                                               bool sun_own = false) {
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 256, seed, 65536, true, BP_LIGHT_SELECTION_POWER).image;
  });
  Sample combined = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 1, true, BP_BETA_CLAMPED, light_rate, light_selection,
                        eye_shared, 1, 4, sun_own)
        .combined;
  });
  for (const std::string& d : significant_differences(combined, reference, runs))
    ADD_FAILURE() << "RB light rate " << light_rate << ", selection "
                  << (light_selection == BP_LIGHT_SELECTION_TREE ? "tree" : "power")
                  << (eye_shared ? ", eye direct shared" : "") << (sun_own ? ", --rb-sun own" : "") << ", " << d;
}

TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderAnAreaLight) {
  expect_light_sampled_combination_unbiased(make_glossy_light_box(), 1.0f, false);
  expect_light_sampled_combination_unbiased(make_glossy_light_box(), 0.25f, true);
}

// Five lights of every kind, some behind a partition: with the light tree, p_L differs per receiving
// patch, and PT and RB must still evaluate the same one (docs/design.md §3, light selection).
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

// A sun through an open ceiling (docs/design.md §6, directional lights): only the light samples reach it,
// PT's and RB's per-patch shadow rays, which carry the indirect light it gives the room. The eye
// vertex's direct light shared with RB is tested on a Lambert floor: on the glossy one RB's eye
// gather reflects a patch's light where its own sample brought none (shadowed, or not taken at rate
// < 1) along the patch normal (a patch-level stand-in, rb_outgoing), which misses a sun's sharp
// highlight by 3-10 % in the block where the sunlit floor meets the shadow.
TEST(Combination, LightSamplingKeepsTheProductWeightsUnbiasedUnderASunThroughAnOpening) {
  Scene scene = make_glossy_light_box();
  std::erase_if(scene.triangles, [](const SceneTriangle& t) { return t.p[0].y > 0.49f && t.p[1].y > 0.49f && t.p[2].y > 0.49f; });
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = glm::vec3(2.0f, 1.8f, 1.5f);
  scene.lights.push_back(sun);
  expect_light_sampled_combination_unbiased(scene, 0.25f, false);
  expect_light_sampled_combination_unbiased(scene, 1.0f, false, BP_LIGHT_SELECTION_POWER);
  // --rb-sun own: RB's patches sample the sun every iteration besides the light they choose (a point
  // light competes with it), and the weights count both
  Scene with_point = scene;
  ScenePunctualLight point;
  point.position = glm::vec3(-0.2f, 0.2f, 0.1f);
  point.intensity = glm::vec3(0.3f, 0.25f, 0.2f);
  with_point.lights.push_back(point);
  expect_light_sampled_combination_unbiased(with_point, 0.25f, false, BP_LIGHT_SELECTION_TREE, true);
  scene.materials[1].kd = glm::vec3(0.6f);  // the floor made Lambert
  scene.materials[1].ks = glm::vec3(0.0f);
  expect_light_sampled_combination_unbiased(scene, 0.25f, true);
  with_point.materials = scene.materials;
  expect_light_sampled_combination_unbiased(with_point, 1.0f, true, BP_LIGHT_SELECTION_TREE, true);
}

// The same scene with the power to see a 2 % bias (issue #12): the image mean and its quadrants of
// many cheap independent combined runs against as many cheap path-traced runs, Welch t-tests at a
// Šidák-corrected family-wise level of 0.01, after asserting that the difference's standard error is
// under 0.7 % of the reference (a 2 % bias is then about 3 standard errors, or more).
struct GlossyCase {
  std::string name;
  std::uint32_t beta;
  bool light_sampling;
  std::uint32_t pt_samples_per_round, rb_iterations_per_round;
  std::uint64_t rounds;
  bool eye_direct_shared = false;
};

TEST(Combination, ImageMeanAndQuadrantsMatchThePathTracerWithThePowerToSeeTwoPercent) {
  Scene scene = make_glossy_light_box();
  const int runs = 24;
  const double max_relative_se = 0.007;
  auto timed = [](auto f) {
    auto start = std::chrono::steady_clock::now();
    auto r = f();
    return std::make_pair(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  };
  auto [reference, ref_seconds] = timed([&] {
    return large_region_runs(runs, 5001, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 64, seed).image; });
  });
  std::printf("[glossy box] PT reference: mean %.5f, rel. se %.3f %%, %.1f s\n", reference.mean[0],
              100.0 * reference.se[0] / reference.mean[0], ref_seconds);
  // Without light sampling RB meets the 0.3 m light in few bundle directions (2.7 % standard error
  // at 32 runs x 64 iterations, N2/N1 4): those cases run PT-heavy, where beta < 1 at nearly every vertex.
  // The clamped beta leaves RB more of the image than the balance one: 16 rounds gave it a standard
  // error of 0.70 %, at the limit; 24 rounds took it to 0.54 %.
  const std::vector<GlossyCase> cases = {
      {"N2/N1 4, beta clamped, light sampling", BP_BETA_CLAMPED, true, 1, 4, 24},
      {"N2/N1 4, beta balance, light sampling", BP_BETA_BALANCE, true, 1, 4, 16},
      {"N2/N1 4, beta balance, light sampling, eye shared", BP_BETA_BALANCE, true, 1, 4, 16, true},
      {"N2/N1 1/16, beta clamped", BP_BETA_CLAMPED, false, 16, 1, 8},
      {"N2/N1 1/16, beta balance", BP_BETA_BALANCE, false, 16, 1, 8},
  };
  const double alpha = sidak_alpha(0.01, int(cases.size()) * kLargeRegions);
  for (const GlossyCase& gc : cases) {
    auto [combined, seconds] = timed([&] {
      return large_region_runs(runs, 9001, [&](std::uint32_t seed) {
        return combined_run(scene, BP_WEIGHTS_PRODUCT, gc.rounds, seed, gc.light_sampling, gc.beta, 1.0f,
                            BP_LIGHT_SELECTION_TREE, gc.eye_direct_shared, gc.pt_samples_per_round,
                            gc.rb_iterations_per_round)
            .combined;
      });
    });
    WelchT mean = welch_t(combined, reference, 0);
    std::printf("[glossy box] %-30s mean %.5f (%+.2f %%), rel. se of the difference %.3f %%, t %+.2f, %.1f s\n",
                gc.name.c_str(), combined.mean[0], 100.0 * (combined.mean[0] / reference.mean[0] - 1.0),
                100.0 * mean.se / reference.mean[0], mean.t, seconds);
    EXPECT_LT(mean.se / reference.mean[0], max_relative_se) << gc.name << ": too noisy to see a 2 % bias";
    for (int i = 0; i < kLargeRegions; ++i) {
      WelchT w = welch_t(combined, reference, i);
      EXPECT_GT(student_t_two_sided_p(w.t, w.dof), alpha)
          << gc.name << ", " << large_region_name(i) << ": " << combined.mean[i] << " vs " << reference.mean[i]
          << " (t " << w.t << ", " << w.dof << " dof)";
    }
  }
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
