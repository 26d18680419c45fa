// Region statistics shared by the kernel tests that compare two estimators: 8x8-block means of
// 32x32 images over independent runs, and per-block t-tests at a Šidák-corrected level.
#pragma once
#include "image/image.h"
#include "stats.h"

#include <cmath>
#include <string>
#include <vector>

namespace bp::test {

constexpr int kSize = 32, kBlock = 8, kBlocksPerSide = kSize / kBlock, kCells = kBlocksPerSide * kBlocksPerSide * 3;

inline std::vector<double> block_means(const ImageRGB& img) {
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

inline double relative_mse(const ImageRGB& image, const std::vector<double>& reference_blocks) {
  std::vector<double> b = block_means(image);
  double sum = 0.0;
  for (int c = 0; c < kCells; ++c) {
    double d = b[c] - reference_blocks[c];
    sum += d * d / (reference_blocks[c] * reference_blocks[c] + 0.01);
  }
  return sum / kCells;
}

// Cells (8x8 blocks x channels, and the image level) where `tested` differs from `reference` beyond a
// t-test at Šidák-corrected alpha 0.01; each Sample holds `runs` independent runs.
inline std::vector<std::string> significant_differences(const Sample& tested, const Sample& reference, int runs) {
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

// Large regions of an image of any size, channels averaged: [0] the image mean, [1..4] its quadrants.
// A bias of a few percent hides in 8x8 blocks at a Šidák-corrected level; it shows in these, over
// many cheap runs.
constexpr int kLargeRegions = 5;
inline const char* large_region_name(int i) {
  static const char* names[kLargeRegions] = {"image mean", "top-left", "top-right", "bottom-left", "bottom-right"};
  return names[i];
}

inline std::vector<double> large_region_means(const ImageRGB& img) {
  std::vector<double> r(kLargeRegions, 0.0);
  const int w = img.width, h = img.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = (img.pixel(x, y)[0] + img.pixel(x, y)[1] + img.pixel(x, y)[2]) / 3.0;
      r[0] += v / (w * h);
      r[1 + (2 * y / h) * 2 + 2 * x / w] += 4.0 * v / (w * h);
    }
  return r;
}

struct RegionRuns {  // mean over independent runs of each large region, its standard error, the run count
  std::vector<double> mean = std::vector<double>(kLargeRegions, 0.0), se = std::vector<double>(kLargeRegions, 0.0);
  int runs = 0;
};

template <class Render>
RegionRuns large_region_runs(int runs, std::uint32_t first_seed, Render render) {
  std::vector<std::vector<double>> all;
  for (int k = 0; k < runs; ++k) all.push_back(large_region_means(render(first_seed + 97u * std::uint32_t(k))));
  RegionRuns r;
  r.runs = runs;
  for (int i = 0; i < kLargeRegions; ++i) {
    for (int k = 0; k < runs; ++k) r.mean[i] += all[k][i] / runs;
    double var = 0.0;
    for (int k = 0; k < runs; ++k) var += (all[k][i] - r.mean[i]) * (all[k][i] - r.mean[i]) / (runs - 1);
    r.se[i] = std::sqrt(var / runs);
  }
  return r;
}

// Welch's t of the difference of two independent RegionRuns in region i, with its degrees of freedom.
struct WelchT {
  double t = 0.0, dof = 1.0, se = 0.0;
};
inline WelchT welch_t(const RegionRuns& a, const RegionRuns& b, int i) {
  WelchT w;
  const double va = a.se[i] * a.se[i], vb = b.se[i] * b.se[i];
  w.se = std::sqrt(va + vb);
  w.t = (a.mean[i] - b.mean[i]) / w.se;
  w.dof = (va + vb) * (va + vb) / (va * va / (a.runs - 1) + vb * vb / (b.runs - 1));
  return w;
}

}  // namespace bp::test
