// The weighted combination on the test device: --weights product converges to the path-traced
// reference (per-region t-tests at the run's sample counts), the error keeps falling with longer
// runs, and the plain sum (--weights none) is caught as biased.
#include "kernel/device_fixture.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>
#include <string>

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

struct Sample {  // per cell, and for the whole image: mean over independent runs and its standard error
  std::vector<double> mean, se;
  double level = 0.0, level_se = 0.0;
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
  std::vector<double> levels(runs, 0.0);
  for (int k = 0; k < runs; ++k)
    for (int c = 0; c < kCells; ++c) levels[k] += all[k][c] / kCells;
  for (int k = 0; k < runs; ++k) s.level += levels[k] / runs;
  double var = 0.0;
  for (int k = 0; k < runs; ++k) var += (levels[k] - s.level) * (levels[k] - s.level) / (runs - 1);
  s.level_se = std::sqrt(var / runs);
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

// Cells (8x8 blocks x channels, and the image level) where `tested` differs from `reference` beyond a
// t-test at Šidák-corrected alpha 0.01; each Sample holds `runs` independent runs.
std::vector<std::string> significant_differences(const Sample& tested, const Sample& reference, int runs) {
  const double alpha = sidak_alpha(0.01, kCells + 1);
  std::vector<std::string> out;
  for (int c = 0; c < kCells; ++c) {
    double t = (tested.mean[c] - reference.mean[c]) / std::hypot(tested.se[c], reference.se[c]);
    if (!(student_t_two_sided_p(t, runs - 1) > alpha))
      out.push_back("cell " + std::to_string(c) + ": " + std::to_string(tested.mean[c]) + " vs " +
                    std::to_string(reference.mean[c]) + " (t " + std::to_string(t) + ")");
  }
  double t = (tested.level - reference.level) / std::hypot(tested.level_se, reference.level_se);
  if (!(student_t_two_sided_p(t, runs - 1) > alpha))
    out.push_back("image level: " + std::to_string(tested.level) + " vs " + std::to_string(reference.level) +
                  " (t " + std::to_string(t) + ")");
  return out;
}

// A glossy floor under a small light: the combination with the product weights converges to the path
// tracer's answer -- no 8x8 block, channel or image level differs significantly between 8 independent
// combined runs and 8 independent path-traced runs -- while the same test catches the plain sum
// (--weights none, every path counted twice).
TEST(Combination, ProductWeightsConvergeToThePathTracedReferenceAndThePlainSumDoesNot) {
  Scene scene = make_glossy_light_box();
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) { return render_pt(scene, kSize, kSize, 512, seed).image; });
  Sample product = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_PRODUCT, 64, seed + 1).combined;  // 64 spp + 256 iterations each
  });
  for (const std::string& d : significant_differences(product, reference, runs)) ADD_FAILURE() << "product weights, " << d;
  Sample none = independent_runs(runs, [&](std::uint32_t seed) {
    return combined_run(scene, BP_WEIGHTS_NONE, 64, seed + 1).combined;
  });
  EXPECT_FALSE(significant_differences(none, reference, runs).empty()) << "the plain sum was not caught";
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
