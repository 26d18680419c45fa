// The regional error (image/regional_error.h) as a user meets it: --stats' regional_error and the
// EXR's region_error layer, checked against the error renders really have. Two renders with
// independent seeds differ per region by the noise of both, Var(Y1 − Y2) = σ1² + σ2² (RB's
// discretisation, the same in both, cancels), so z = (Y1 − Y2) / √(σ1² + σ2²) over many regions and
// seed pairs must look standard normal: mean z² near 1, no |z| beyond a Šidák-corrected bound. Per
// pixel variances summed over a region (the stderr layer as if pixels were independent) would not:
// RB's chain moves whole regions together.
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "image/regions.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <fstream>
#include <vector>

namespace bp::test {
namespace {

const std::string kBox = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf ";

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

struct Render {
  std::vector<double> mean, stderr_of_mean, pixel_stderr_sum;  // per region: luminance
};

// The render's regions as its stats report them, and the stderr layer's per-pixel variances summed
// over each region as if the pixels were independent.
Render read_render(const std::string& out, int width, int height) {
  const nlohmann::json r = read_json(out + ".json")["regional_error"];
  Render out_render;
  for (std::size_t b = 0; b < r["mean_luminance"].size(); ++b) {
    const double m = r["mean_luminance"][b].get<double>();
    out_render.mean.push_back(m);
    out_render.stderr_of_mean.push_back(r["relative_stderr"][b].is_null() ? NAN : r["relative_stderr"][b].get<double>() * m);
  }
  const ImageRGB se = read_exr(out + ".exr", "stderr");
  const RegionGrid g = RegionGrid::over(width, height, r["regions"][0].get<int>(), r["regions"][1].get<int>());
  std::vector<double> var(g.count(), 0.0);
  const std::vector<std::size_t> n = g.pixel_counts();
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* p = &se.rgb[(std::size_t(y) * width + x) * 3];
      const double y_se = luminance(p[0], p[1], p[2]);  // at most the luminance's standard error
      var[g.region_of(x, y)] += y_se * y_se;
    }
  for (std::size_t b = 0; b < var.size(); ++b) out_render.pixel_stderr_sum.push_back(std::sqrt(var[b]) / double(n[b]));
  return out_render;
}

// Six seeds, three pairs, 64 regions each, less the black ones: about 140 z-scores. Mean z² is
// 1 ± 0.12 for a right estimate (RB's batches here: 32 of 16 iterations, pooled over the regions, so
// the estimated variances have about 39 degrees of freedom and E[z²] ≈ 1.05); a variance estimate off
// by 2x moves it to 0.5 or 2.
TEST(RegionalErrorCli, SeedPairsDifferByTheRegionalErrorTheRendersReport) {
  const std::string dir = fresh_dir("regional_error_pairs");
  constexpr int kWidth = 64, kHeight = 48, kSeeds = 6;
  for (const std::string options : {"", "--rb-level own", "--mode pt --spp 128"}) {
    std::vector<Render> renders;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const std::string out = dir + "/s" + std::to_string(seed);
      const std::string budget = options.find("--mode pt") == std::string::npos ? "--ratio 1/4 --iterations 512 " : "";
      CliResult r = run_cli("render " + kBox + "--width " + std::to_string(kWidth) + " --height " +
                            std::to_string(kHeight) + " " + budget + options + " --seed " + std::to_string(seed) +
                            " --out " + out + " --stats " + out + ".json");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      renders.push_back(read_render(out, kWidth, kHeight));
    }
    double sum_z2 = 0.0, largest_z = 0.0, sum_pixel_z2 = 0.0;
    int count = 0;
    for (int k = 0; k + 1 < kSeeds; k += 2) {
      const Render &a = renders[std::size_t(k)], &b = renders[std::size_t(k) + 1];
      for (std::size_t r = 0; r < a.mean.size(); ++r) {
        const double sd = std::hypot(a.stderr_of_mean[r], b.stderr_of_mean[r]);
        if (!(sd > 0.0) || a.mean[r] <= 0.0) continue;  // a black region
        const double z = (a.mean[r] - b.mean[r]) / sd;
        sum_z2 += z * z;
        largest_z = std::max(largest_z, std::fabs(z));
        const double pixel_z = (a.mean[r] - b.mean[r]) / std::hypot(a.pixel_stderr_sum[r], b.pixel_stderr_sum[r]);
        sum_pixel_z2 += pixel_z * pixel_z;
        ++count;
      }
    }
    ASSERT_GT(count, 120) << options;  // the box's black regions (its open front's edges) left out
    const double mean_z2 = sum_z2 / count;
    std::printf("%-22s regions %d: mean z^2 %.3f (per-pixel variances summed: %.3f), largest |z| %.2f\n",
                options.empty() ? "(defaults)" : options.c_str(), count, mean_z2, sum_pixel_z2 / count, largest_z);
    EXPECT_GT(mean_z2, 0.6) << options;
    EXPECT_LT(mean_z2, 1.6) << options;
    // Šidák over ~140 regions at a family-wise 1e-3: |z| < 5 even with the t tails of 15 freedoms.
    EXPECT_LT(largest_z, 5.0) << options;
  }
}

// --target-block-error: the render stops once its expected worst region is within the target, and
// the worst region's error it really has (half the difference of two seeds' region means, scaled
// to one render: |Y1 − Y2| / √2 over the mean) is within 1.5x of it.
TEST(RegionalErrorCli, TargetBlockErrorStopsNearTheWorstRegionsError) {
  const std::string dir = fresh_dir("regional_error_target");
  constexpr double kTarget = 0.05;
  std::vector<Render> renders;
  for (int seed = 1; seed <= 2; ++seed) {
    const std::string out = dir + "/s" + std::to_string(seed);
    CliResult r = run_cli("render " + kBox + "--width 64 --height 48 --ratio 1/4 --target-block-error 0.05 --seed " +
                          std::to_string(seed) + " --out " + out + " --stats " + out + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json stats = read_json(out + ".json");
    EXPECT_EQ(stats["target_reached"], true);
    EXPECT_LE(stats["regional_error"]["expected_worst_error"].get<double>(), kTarget);
    EXPECT_GE(stats["regional_error"]["degrees_of_freedom"].get<double>(), 7.0);
    renders.push_back(read_render(out, 64, 48));
  }
  double worst = 0.0;
  for (std::size_t r = 0; r < renders[0].mean.size(); ++r) {
    const double m = 0.5 * (renders[0].mean[r] + renders[1].mean[r]);
    if (m > 0.0) worst = std::max(worst, std::fabs(renders[0].mean[r] - renders[1].mean[r]) / std::sqrt(2.0) / m);
  }
  std::printf("target %.3f: worst region off by %.4f (from two seeds)\n", kTarget, worst);
  EXPECT_LT(worst, 1.5 * kTarget);
  EXPECT_GT(worst, kTarget / 1.5);
  CliResult bad = run_cli("render " + kBox + "--target-block-error 0");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--target-block-error"), std::string::npos) << bad.output;
  CliResult with_spp = run_cli("render " + kBox + "--target-block-error 0.02 --spp 4");
  EXPECT_EQ(with_spp.exit_code, 2);
}

// A regional estimate from few degrees of freedom is said to be rough: the path tracer alone at 2 spp
// on regions of 2x1.5 pixels has about one, at 64 spp on regions of 8x6 pixels more than seven.
TEST(RegionalErrorCli, AnEstimateFromFewDegreesOfFreedomIsSaidToBeRough) {
  const std::string dir = fresh_dir("regional_error_rough");
  CliResult few = run_cli("render " + kBox + "--width 16 --height 12 --mode pt --spp 2 --out " + dir + "/few");
  ASSERT_EQ(few.exit_code, 0) << few.output;
  EXPECT_NE(few.output.find("rough, from 1 degrees of freedom"), std::string::npos) << few.output;
  CliResult enough = run_cli("render " + kBox + "--width 64 --height 48 --mode pt --spp 64 --out " + dir +
                             "/enough --stats " + dir + "/enough.json");
  ASSERT_EQ(enough.exit_code, 0) << enough.output;
  EXPECT_GE(read_json(dir + "/enough.json")["regional_error"]["degrees_of_freedom"].get<double>(), 7.0);
  EXPECT_NE(enough.output.find("regions expected off by"), std::string::npos) << enough.output;
  EXPECT_EQ(enough.output.find("; rough"), std::string::npos) << enough.output;
}

// A render of one batch cannot measure its noise (the batches' spread): it says so instead of saying
// nothing, for the path tracer alone and for the combination (one round: one PT batch, no RB batch closed).
TEST(RegionalErrorCli, ARenderOfOneBatchSaysItHasNoErrorEstimate) {
  const std::string dir = fresh_dir("regional_error_one_batch");
  for (const std::string flags : {"--mode pt --spp 1", "--ratio 1/16 --spp 1"}) {
    CliResult one = run_cli("render " + kBox + "--width 16 --height 12 " + flags + " --out " + dir + "/one");
    ASSERT_EQ(one.exit_code, 0) << one.output;
    EXPECT_NE(one.output.find("no error estimate: it needs two batches or more"), std::string::npos) << one.output;
    EXPECT_EQ(one.output.find("estimated relMSE"), std::string::npos) << one.output;
  }
  CliResult two = run_cli("render " + kBox + "--width 16 --height 12 --mode pt --spp 2 --out " + dir + "/two");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_NE(two.output.find("estimated relMSE"), std::string::npos) << two.output;
  EXPECT_EQ(two.output.find("no error estimate"), std::string::npos) << two.output;
}

}  // namespace
}  // namespace bp::test
