// The check of the combination against the path tracer with the power to see a 2 % bias (the glass
// and cluster tests), as Combination's glossy-box test: the image mean and its quadrants of many cheap combined
// runs against as many path-traced ones (Welch t-tests at a Šidák-corrected 0.01), once the
// difference's standard error is under 0.7 % of the reference. RB takes most of the image at N2/N1 4
// (light sampling on, eye direct shared), PT at N2/N1 1/16 (off), so a share given to the wrong
// estimator shows in one of the two.
#pragma once
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cstdio>
#include <iterator>

namespace bp::test {

struct PowerCase {
  const char* name;
  bool light_sampling, eye_shared;
  std::uint64_t rounds;
  std::uint32_t pt_samples_per_round, rb_iterations_per_round, beta;
};

// One combined run of a case (product weights, patches of 0.05 m, RB's light-sample rate 1/2;
// cluster_size > 0: the patches clustered, scene/clusters.h).
inline CombinedRun power_run(const Scene& scene, std::uint32_t seed, const PowerCase& c, float cluster_size) {
  CombinedSettings cs;
  cs.weight_mode = BP_WEIGHTS_PRODUCT;
  cs.seed = seed;
  cs.rounds = c.rounds;
  cs.pt_samples_per_round = c.pt_samples_per_round;
  cs.rb_iterations_per_round = c.rb_iterations_per_round;
  cs.beta_heuristic = c.beta;
  cs.patch_size = 0.05f;
  cs.light_sampling = c.light_sampling;
  cs.light_rate = 0.5f;
  cs.eye_direct_shared = c.eye_shared;
  cs.cluster_size = cluster_size;
  return render_combined(scene, kSize, kSize, cs);
}

inline void expect_combination_matches_pt_with_power_to_see_two_percent(const Scene& scene, const char* label,
                                                                        float cluster_size = 0.0f) {
  const int runs = 24;
  const RegionRuns reference =
      large_region_runs(runs, 5001, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 64, seed).image; });
  const PowerCase cases[] = {
      {"N2/N1 4, beta clamped, light sampling, eye shared", true, true, 24, 1, 4, BP_BETA_CLAMPED},
      {"N2/N1 1/16, beta balance", false, false, 8, 16, 1, BP_BETA_BALANCE},
  };
  const double alpha = sidak_alpha(0.01, int(std::size(cases)) * kLargeRegions);
  for (const PowerCase& c : cases) {
    const RegionRuns tested =
        large_region_runs(runs, 9001, [&](std::uint32_t seed) { return power_run(scene, seed, c, cluster_size).combined; });
    const WelchT mean = welch_t(tested, reference, 0);
    std::printf("[%s] %-50s mean %.5f (%+.2f %%), rel. se of the difference %.3f %%, t %+.2f\n", label, c.name,
                tested.mean[0], 100.0 * (tested.mean[0] / reference.mean[0] - 1.0), 100.0 * mean.se / reference.mean[0],
                mean.t);
    EXPECT_LT(mean.se / reference.mean[0], 0.007) << c.name << ": too noisy to see a 2 % bias";
    for (int i = 0; i < kLargeRegions; ++i) {
      const WelchT w = welch_t(tested, reference, i);
      EXPECT_GT(student_t_two_sided_p(w.t, w.dof), alpha)
          << c.name << ", " << large_region_name(i) << ": " << tested.mean[i] << " vs " << reference.mean[i] << " (t "
          << w.t << ", " << w.dof << " dof)";
    }
  }
}

}  // namespace bp::test
