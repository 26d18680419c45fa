// The weighted combination on the test device: --weights product converges to the path-traced
// reference (per-region t-tests at the run's sample counts), the error keeps falling with longer
// runs, and the plain sum (--weights none) is caught as biased.
#include "kernel/device_fixture.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

constexpr int kSize = 32, kBlock = 8, kBlocksPerSide = kSize / kBlock, kCells = kBlocksPerSide * kBlocksPerSide * 3;

std::vector<double> block_means(const ImageRGB& img) {
  std::vector<double> b(kCells, 0.0);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c)
        b[((y / kBlock) * kBlocksPerSide + x / kBlock) * 3 + c] += img.pixel(x, y)[c] / (kBlock * kBlock);
  return b;
}

struct Sample {  // per cell: mean over independent runs and the standard error of that mean
  std::vector<double> mean, se;
};

template <class Render>
Sample independent_runs(int runs, Render render) {
  std::vector<std::vector<double>> all;
  for (int k = 0; k < runs; ++k) all.push_back(block_means(render(std::uint32_t(1000 + 37 * k))));
  Sample s{std::vector<double>(kCells, 0.0), std::vector<double>(kCells, 0.0)};
  for (int c = 0; c < kCells; ++c) {
    for (int k = 0; k < runs; ++k) s.mean[c] += all[k][c] / runs;
    double var = 0.0;
    for (int k = 0; k < runs; ++k) var += (all[k][c] - s.mean[c]) * (all[k][c] - s.mean[c]) / (runs - 1);
    s.se[c] = std::sqrt(var / runs);
  }
  return s;
}

double relative_mse(const ImageRGB& image, const std::vector<double>& reference_blocks) {
  std::vector<double> b = block_means(image);
  double sum = 0.0;
  for (int c = 0; c < kCells; ++c) {
    double d = b[c] - reference_blocks[c];
    sum += d * d / (reference_blocks[c] * reference_blocks[c] + 0.01);
  }
  return sum / kCells;
}

CombinedRun combined_run(const Scene& scene, std::uint32_t mode, std::uint64_t rounds, std::uint32_t seed) {
  CombinedSettings cs;
  cs.weight_mode = mode;
  cs.seed = seed;
  cs.rounds = rounds;
  cs.patch_size = 0.05f;
  return render_combined(scene, kSize, kSize, cs);
}

// A glossy floor under a small light: the combination with the product weights converges to the path
// tracer's answer. Every 8x8 block and channel: a t-test of 8 independent combined runs against 8
// independent path-traced runs (Šidák over all cells, alpha 0.01); and the image level within 3 %.
TEST(Combination, ProductWeightsConvergeToThePathTracedReference) {
  Scene scene = make_glossy_light_box();
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 512, seed).image; });
  Sample combined = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 1).combined;  // 64 spp + 256 iterations each
  });
  const double alpha = sidak_alpha(0.01, kCells);
  double level = 0.0, reference_level = 0.0;
  for (int c = 0; c < kCells; ++c) {
    double se = std::sqrt(combined.se[c] * combined.se[c] + reference.se[c] * reference.se[c]);
    double t = (combined.mean[c] - reference.mean[c]) / se;
    EXPECT_GT(student_t_two_sided_p(t, runs - 1), alpha)
        << "cell " << c << ": combined " << combined.mean[c] << " reference " << reference.mean[c] << " (t " << t << ")";
    level += combined.mean[c] / kCells;
    reference_level += reference.mean[c] / kCells;
  }
  EXPECT_NEAR(level / reference_level, 1.0, 0.03) << "combined level " << level << " reference " << reference_level;
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

TEST(Combination, PlainSumWithoutWeightsIsCaughtAsBiased) {
  // The comparison above can fail: without weights every path is counted twice.
  Scene scene = make_glossy_light_box();
  Sample reference = independent_runs(4, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 256, seed).image; });
  Sample none = independent_runs(4, [&](std::uint32_t seed) { return combined_run(scene, BP_WEIGHTS_NONE, 16, seed).combined; });
  double level = 0.0, reference_level = 0.0;
  for (int c = 0; c < kCells; ++c) {
    level += none.mean[c];
    reference_level += reference.mean[c];
  }
  EXPECT_GT(level / reference_level, 1.6);
}

}  // namespace
}  // namespace bp::test
